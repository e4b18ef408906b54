// The SDK subscriber's state machine and options on their own, without a server: every state
// and the transitions between them, and bad options named before any DDS entity exists.
// (tests/client_test.cc runs the same states against a real omnisweep-server.)
#include "omnisweep/client/rgbd_subscriber.h"

#include <gtest/gtest.h>

#include "tests/support/test_support.h"

namespace omnisweep::client {
namespace {

constexpr double kStallAfter = 2.0;

ConnectionState state_of(const ConnectionInputs& in) { return connection_state(in, kStallAfter); }

TEST(ConnectionState, NoServerThenWaitingThenReceivingThenStalled) {
  ConnectionInputs in;
  EXPECT_EQ(state_of(in), ConnectionState::kNoServer);
  in.matched_servers = 1;  // a server matched, computing its first frame
  in.since_frame_s = 100;
  EXPECT_EQ(state_of(in), ConnectionState::kWaiting);
  in.frames_received = 1;  // the first frame
  in.since_frame_s = 0.1;
  EXPECT_EQ(state_of(in), ConnectionState::kReceiving);
  in.since_frame_s = 1.99;
  EXPECT_EQ(state_of(in), ConnectionState::kReceiving);
  in.since_frame_s = 2.0;  // no frame for stall_after_s, the server still matched
  EXPECT_EQ(state_of(in), ConnectionState::kStalled);
  in.matched_servers = 0;  // the server went away
  EXPECT_EQ(state_of(in), ConnectionState::kNoServer);
  in.since_frame_s = 0.5;  // its last frames still count as receiving until they stop
  EXPECT_EQ(state_of(in), ConnectionState::kReceiving);
}

TEST(ConnectionState, ASlowServerThatKeepsReportingIsNotStalled) {
  ConnectionInputs in{.frames_received = 3,
                      .since_frame_s = 6.0,
                      .since_status_s = 0.5,
                      .server_running = true,
                      .server_frame_s = 3.0,  // 3 s per frame: allowed 2 * 3 + 1 = 7 s
                      .matched_servers = 1};
  EXPECT_EQ(state_of(in), ConnectionState::kReceiving);
  in.since_frame_s = 7.0;
  EXPECT_EQ(state_of(in), ConnectionState::kStalled);
  in.since_frame_s = 6.0;
  in.since_status_s = 2.5;  // its status stopped too
  EXPECT_EQ(state_of(in), ConnectionState::kStalled);
  in.since_status_s = 0.5;
  in.server_running = false;  // reporting, but not running (source stalled, stopping)
  EXPECT_EQ(state_of(in), ConnectionState::kStalled);
  in.server_running = true;
  in.server_frame_s = 0.1;  // a fast server: stall_after_s is the bound
  in.since_frame_s = 2.5;
  EXPECT_EQ(state_of(in), ConnectionState::kStalled);
}

TEST(ConnectionState, EveryStateHasAName) {
  EXPECT_STREQ(to_string(ConnectionState::kNoServer), "no server");
  EXPECT_STREQ(to_string(ConnectionState::kWaiting), "waiting for the first frame");
  EXPECT_STREQ(to_string(ConnectionState::kReceiving), "receiving");
  EXPECT_STREQ(to_string(ConnectionState::kStalled), "stalled");
}

// Bad subscriber options are options errors naming the field, before any DDS entity exists.
TEST(SubscriberOptions, BadOptionsAreNamed) {
  SubscriberOptions options;
  options.stall_after_s = -2;
  EXPECT_EQ(
      testing::error_message<std::invalid_argument>([&] { RgbdSubscriber subscriber(options); }),
      "SubscriberOptions.stall_after_s = -2: must be a positive number of seconds");
  options = {};
  options.profile.clear();
  EXPECT_THROW(options.check(), std::invalid_argument);
}

}  // namespace
}  // namespace omnisweep::client
