// The client side as apps and users meet it, against omnisweep-server on loopback: the SDK's
// subscriber reports its connection state as the server runs, freezes and stops; omnisweep-view
// writes its PNGs after --frames N and fails clearly when nothing arrives in time.
#include <gtest/gtest.h>

#include <csignal>
#include <memory>
#include <regex>
#include <thread>

#include "omnisweep/client/rgbd_subscriber.h"
#include "omnisweep/dds/stream_publisher.h"
#include "omnisweep/image/image_io.h"
#include "tests/support/stream_fixture.h"

namespace omnisweep {
namespace {

namespace fs = std::filesystem;
using client::ConnectionState;
using testing::BackgroundProcess;
using testing::run_command;

class ClientTest : public testing::StreamTest {};

// Polls `subscriber` until it reports `state`, up to `seconds`.
bool reaches(const client::RgbdSubscriber& subscriber, ConnectionState state, double seconds) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (std::chrono::steady_clock::now() < deadline) {
    if (subscriber.state() == state) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return subscriber.state() == state;
}

TEST_F(ClientTest, SubscriberReportsReceivingStalledAndNoServer) {
  client::SubscriberOptions options{.participant = participant_options(), .stall_after_s = 1.0};
  client::RgbdSubscriber subscriber(options);
  EXPECT_EQ(subscriber.state(), ConnectionState::kNoServer);
  BackgroundProcess server(server_command(), dir_.path() / "server.log");

  const auto frame = subscriber.wait_for_frame(std::chrono::seconds(60));
  ASSERT_TRUE(frame) << server.log();
  EXPECT_EQ(subscriber.state(), ConnectionState::kReceiving);
  EXPECT_EQ(frame->color.width(), 256);
  EXPECT_EQ(frame->distance.height(), 128);
  EXPECT_GT(frame->latency_ms(), 0.0);
  EXPECT_EQ(frame->capture_time_ns.size(), 4u);
  EXPECT_GT(frame->color_bytes + frame->distance_bytes, 0u);
  ASSERT_TRUE(subscriber.latest_frame());
  EXPECT_GE(subscriber.latest_frame()->sequence_number, frame->sequence_number);
  for (int i = 0; i < 100 && !subscriber.status(); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  EXPECT_TRUE(subscriber.status()) << "no status within 5 s";
  ASSERT_TRUE(subscriber.stream_info());
  EXPECT_EQ(subscriber.stream_info()->rig.num_cameras(), 4);

  // Frozen: still matched (its DDS lease runs on), but no frames: stalled, then receiving again.
  server.signal(SIGSTOP);
  EXPECT_TRUE(reaches(subscriber, ConnectionState::kStalled, 5));
  server.signal(SIGCONT);
  EXPECT_TRUE(reaches(subscriber, ConnectionState::kReceiving, 20));
  // Stopped cleanly: its writers leave, so no server.
  double seconds = 0;
  EXPECT_EQ(server.stop(SIGTERM, 5, &seconds), 0);
  EXPECT_TRUE(reaches(subscriber, ConnectionState::kNoServer, 5));
  EXPECT_EQ(subscriber.stats().decode_errors, 0u);
}

// A server status message with `state` and per-stage milliseconds, as a test's own server sends.
msg::ServerStatus status_of(const std::string& state,
                            const std::vector<std::pair<std::string, float>>& stages) {
  msg::ServerStatus status;
  status.state(state);
  std::vector<msg::StageTime> times;
  for (const auto& [name, ms] : stages) {
    times.emplace_back();
    times.back().stage(name);
    times.back().ms(ms);
  }
  status.stage_ms(times);
  return status;
}

// A server still computing its first frame (slow on a CPU device): matched, publishing status,
// no frame yet. The SDK says "waiting", not "stalled"; the viewer and the subscriber say so and
// show what the server's status says it is doing.
TEST_F(ClientTest, WaitingForTheFirstFrameIsNotStalled) {
  dds::StreamPublisher server(participant_options());
  client::SubscriberOptions options{.participant = participant_options(), .stall_after_s = 0.5};
  client::RgbdSubscriber subscriber(options);
  msg::ServerStatus status = status_of("starting", {{"capture", 1234.0f}, {"depth", 0.0f}});
  std::atomic<bool> done{false};
  std::thread statuses([&] {  // once every 200 ms, as a server does once a second
    while (!done) {
      status.time_ns(std::uint64_t(std::chrono::system_clock::now().time_since_epoch().count()));
      server.publish(status);
      std::this_thread::sleep_for(std::chrono::milliseconds(200));
    }
  });
  EXPECT_TRUE(reaches(subscriber, ConnectionState::kWaiting, 30));
  std::this_thread::sleep_for(std::chrono::seconds(1));  // past stall_after_s: still waiting
  EXPECT_EQ(subscriber.state(), ConnectionState::kWaiting);
  EXPECT_STREQ(client::to_string(ConnectionState::kWaiting), "waiting for the first frame");
  const std::string expected =
      "waiting for the first frame (server starting; per frame: capture 1234 ms)";
  std::string log;
  EXPECT_EQ(run_command(tool_command("view", " --frames 1 --timeout 6 --output " +
                                                 (dir_.path() / "view").string()),
                        &log),
            1);
  EXPECT_NE(log.find(expected), std::string::npos) << log;
  EXPECT_EQ(log.find("stalled"), std::string::npos) << log;
  EXPECT_NE(log.find("with 0 of 1 frames (waiting for the first frame)"), std::string::npos) << log;
  EXPECT_EQ(run_command(tool_command("subscribe", " --frames 1 --timeout 6"), &log), 1);
  EXPECT_NE(log.find(expected), std::string::npos) << log;
  done = true;
  statuses.join();
}

// A running server slower than stall_after_s per frame (a CPU device) is not stalled between its
// frames while its status keeps coming; once the status stops too, the stream is stalled.
TEST_F(ClientTest, SlowServerIsNotStalledBetweenFrames) {
  dds::StreamPublisher server(participant_options());
  client::SubscriberOptions options{.participant = participant_options(), .stall_after_s = 0.5};
  client::RgbdSubscriber subscriber(options);
  msg::ServerStatus status = status_of("running", {{"depth", 3000.0f}});  // 3 s a frame
  std::atomic<bool> statuses_on{true}, done{false};
  std::thread statuses([&] {
    while (!done) {
      if (statuses_on) server.publish(status);
      std::this_thread::sleep_for(std::chrono::milliseconds(200));
    }
  });
  // Joined however the test ends (a failed ASSERT returns early).
  const std::unique_ptr<std::thread, void (*)(std::thread*)> join(&statuses, [](std::thread* t) {
    if (t->joinable()) t->join();
  });
  const struct Stop {
    std::atomic<bool>& done;
    ~Stop() { done = true; }
  } stop{done};
  // Discovery: about a second here, but a loaded CI machine once took over 10.
  ASSERT_TRUE(reaches(subscriber, ConnectionState::kWaiting, 30));
  msg::RgbdFrame frame;  // payloads do not matter here: a frame arrived
  frame.sequence_number(1);
  for (int i = 0; i < 100 && subscriber.stats().frames_received == 0; ++i) {
    server.publish(frame);
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  ASSERT_GT(subscriber.stats().frames_received, 0u);
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));  // 3 x stall_after_s, < 7 s
  EXPECT_EQ(subscriber.state(), ConnectionState::kReceiving);
  statuses_on = false;  // the server froze: no status either
  EXPECT_TRUE(reaches(subscriber, ConnectionState::kStalled, 5));
}

TEST_F(ClientTest, ViewWritesThePanoramaItsDistanceAndANovelView) {
  BackgroundProcess server(server_command(), dir_.path() / "server.log");
  const fs::path out = dir_.path() / "view";
  std::string log;
  ASSERT_EQ(run_command(tool_command("view",
                                     " --frames 2 --timeout 60 --write-interval 0"
                                     " --offset 0.05 0 0 --yaw 30 --pinhole 160 120 90"
                                     " --output " +
                                         out.string()),
                        &log),
            0)
      << log << server.log();
  std::smatch decoded;
  ASSERT_TRUE(std::regex_search(log, decoded, std::regex(R"(summary: (\d+) frames decoded)")))
      << log;
  EXPECT_GE(std::stoi(decoded[1]), 2) << log;  // a third may land before it stops
  EXPECT_NE(log.find(out.string()), std::string::npos) << "says where the images are: " << log;
  const std::pair<const char*, int> files[] = {{"panorama.png", 256},
                                               {"panorama_inverse_distance.png", 256},
                                               {"view.png", 160},
                                               {"view_inverse_distance.png", 160}};
  for (const auto& [name, width] : files) {
    ASSERT_TRUE(fs::exists(out / name)) << name << "\n" << log;
    EXPECT_EQ(width_of(read_color_image(out / name)), width) << name;
  }
}

// The optional confidence: a subscriber that asks gets it with each frame, in [0, 1] at the
// frame's size; one that does not ask (any subscriber from before the topic existed) decodes
// the same frames as before, with no confidence and nothing counted against it.
TEST_F(ClientTest, ConfidenceReachesThoseWhoAskAndNoOneElse) {
  BackgroundProcess server(server_command(" --confidence"), dir_.path() / "server.log");
  client::SubscriberOptions asking;
  asking.participant = participant_options();
  asking.confidence = true;
  client::SubscriberOptions plain;
  plain.participant = participant_options();
  client::RgbdSubscriber with(asking), without(plain);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(90);
  std::shared_ptr<const client::RgbdFrame> frame;
  while (std::chrono::steady_clock::now() < deadline) {
    frame = with.latest_frame();
    if (frame && !frame->confidence.empty() && without.latest_frame()) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  ASSERT_TRUE(frame && !frame->confidence.empty()) << with.stats().last_error << "\n"
                                                   << server.log();
  EXPECT_EQ(frame->confidence.width(), frame->distance.width());
  EXPECT_EQ(frame->confidence.height(), frame->distance.height());
  double mean = 0;
  for (const float c : frame->confidence.pixels()) {
    ASSERT_TRUE(c >= 0 && c <= 1) << c;
    mean += c / double(frame->confidence.size());
  }
  EXPECT_GT(mean, 0.05) << "a confidence map, not an empty one";
  const auto plain_frame = without.latest_frame();
  ASSERT_TRUE(plain_frame);
  EXPECT_TRUE(plain_frame->confidence.empty());
  EXPECT_EQ(without.stats().frames_without_confidence, 0u);
  EXPECT_EQ(without.stats().decode_errors, 0u);

  // omnisweep-view writes it beside the panorama.
  const fs::path out = dir_.path() / "view";
  std::string log;
  ASSERT_EQ(run_command(tool_command("view",
                                     " --confidence --min-confidence 0.2 --frames 2"
                                     " --timeout 60 --write-interval 0"
                                     " --pinhole 160 120 90 --output " +
                                         out.string()),
                        &log),
            0)
      << log << server.log();
  ASSERT_TRUE(fs::exists(out / "panorama_confidence.png")) << log;
  EXPECT_EQ(read_gray8_image(out / "panorama_confidence.png").width(), 256);
}

TEST_F(ClientTest, ViewWithoutAServerTimesOutWithAClearError) {
  std::string log;
  const auto start = std::chrono::steady_clock::now();
  EXPECT_EQ(run_command(tool_command("view", " --frames 1 --timeout 2 --output " +
                                                 (dir_.path() / "none").string()),
                        &log),
            1)
      << log;
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(10));
  EXPECT_NE(log.find("timed out after 2.0 s with 0 of 1 frames (no server)"), std::string::npos)
      << log;
  EXPECT_NE(run_command(tool_command("view", " --pinhole 0 10 90"), &log), 0);
  EXPECT_NE(log.find("--pinhole"), std::string::npos) << log;
}

}  // namespace
}  // namespace omnisweep
