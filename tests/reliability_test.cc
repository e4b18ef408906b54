// Faults on loopback, as a robot's network and power meet them: a server killed with SIGKILL
// and started again reaches a subscriber that kept running; a subscriber blocked in its
// callback slows neither the server nor another subscriber. (ctest label: reliability)
#include <gtest/gtest.h>

#include <atomic>
#include <csignal>
#include <map>
#include <regex>
#include <thread>

#include "omnisweep/client/rgbd_subscriber.h"
#include "tests/support/stream_fixture.h"

namespace omnisweep {
namespace {

using Clock = std::chrono::steady_clock;
using testing::BackgroundProcess;

class ReliabilityTest : public testing::StreamTest {};

double seconds_since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

TEST_F(ReliabilityTest, SubscriberResumesAfterTheServerIsKilledAndRestarted) {
  client::SubscriberOptions options{.participant = participant_options()};
  client::RgbdSubscriber subscriber(options);
  std::uint64_t first_revision = 0;
  {
    BackgroundProcess server(server_command(), dir_.path() / "server1.log");
    ASSERT_TRUE(subscriber.wait_for_frame(std::chrono::seconds(60))) << server.log();
    for (int i = 0; i < 100 && !subscriber.stream_info(); ++i)
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    ASSERT_TRUE(subscriber.stream_info());
    first_revision = subscriber.stream_info()->revision;
    double seconds = 0;
    server.stop(SIGKILL, 5, &seconds);
  }
  std::this_thread::sleep_for(std::chrono::seconds(1));
  // The same server started again: new frames and the calibration reach the same subscriber.
  const auto restarted = Clock::now();
  BackgroundProcess server(server_command(), dir_.path() / "server2.log");
  std::shared_ptr<const client::RgbdFrame> frame;
  while (seconds_since(restarted) < 30) {
    frame = subscriber.wait_for_frame(std::chrono::milliseconds(500));
    if (frame && frame->description_revision != first_revision) break;
  }
  const double resumed_s = seconds_since(restarted);
  ASSERT_TRUE(frame && frame->description_revision != first_revision) << server.log();
  std::printf("frames from the restarted server after %.2f s\n", resumed_s);
  EXPECT_LT(resumed_s, 5.0);
  for (int i = 0; i < 100 && subscriber.stream_info()->revision == first_revision; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  EXPECT_EQ(subscriber.stream_info()->revision, frame->description_revision)
      << "the restarted server's calibration did not arrive";
  EXPECT_EQ(subscriber.state(), client::ConnectionState::kReceiving);
}

TEST_F(ReliabilityTest, BlockedSubscriberSlowsNeitherTheServerNorAnother) {
  BackgroundProcess server(server_command(), dir_.path() / "server.log");
  std::atomic<int> slow_frames{0}, fast_frames{0};
  client::SubscriberOptions options{.participant = participant_options()};
  client::RgbdSubscriber slow(options, [&](const std::shared_ptr<const client::RgbdFrame>&) {
    ++slow_frames;
    std::this_thread::sleep_for(std::chrono::seconds(3));  // an app stuck in its callback
  });
  client::RgbdSubscriber fast(
      options, [&](const std::shared_ptr<const client::RgbdFrame>&) { ++fast_frames; });
  ASSERT_TRUE(fast.wait_for_frame(std::chrono::seconds(60))) << server.log();
  std::this_thread::sleep_for(std::chrono::seconds(1));
  const int fast_before = fast_frames;
  const auto start = Clock::now();
  // The server's own rate from its status messages (one a second) over the same window.
  std::map<std::uint64_t, float> server_fps;
  while (seconds_since(start) < 6) {
    if (const auto status = fast.status()) server_fps[status->time_ns()] = status->fps_out();
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  const double fast_fps = (fast_frames - fast_before) / seconds_since(start);
  ASSERT_GE(server_fps.size(), 4u);
  double server_mean = 0;
  for (const auto& [time, fps] : server_fps) server_mean += fps / double(server_fps.size());
  std::printf(
      "server %.2f fps out (mean of %zu statuses), other subscriber %.2f fps, blocked "
      "subscriber %d frames in its callback\n",
      server_mean, server_fps.size(), fast_fps, slow_frames.load());
  // Neither the server nor the other reader falls to the blocked reader's pace (one frame per
  // 3 s); the other reader keeps up with what the server publishes.
  EXPECT_GT(server_mean, 2.5);
  EXPECT_GT(fast_fps, 0.8 * server_mean);
  EXPECT_LE(slow_frames, 4);
}

}  // namespace
}  // namespace omnisweep
