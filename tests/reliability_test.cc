// Faults on loopback, as a robot's network and power meet them: a server killed with SIGKILL
// and started again reaches a subscriber that kept running; a subscriber blocked in its
// callback slows neither the server nor another subscriber; eight subscribers cost the server
// little more than one; a source that stalls is reported, and ends the server where configured.
// (ctest label: reliability)
#include <gtest/gtest.h>

#include <atomic>
#include <csignal>
#include <filesystem>
#include <map>
#include <memory>
#include <regex>
#include <thread>
#include <vector>

#include "omnisweep/client/rgbd_subscriber.h"
#include "omnisweep/dds/stream_subscriber.h"
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

// The server's frames out per second and publish time (ms), means over `seconds` of status.
std::pair<double, double> server_load(const dds::StreamSubscriber& subscriber, double seconds) {
  std::map<std::uint64_t, std::pair<float, float>> seen;  // status time -> fps out, publish ms
  const auto start = Clock::now();
  while (seconds_since(start) < seconds) {
    if (const auto s = subscriber.status()) {
      for (const auto& stage : s->stage_ms())
        if (stage.stage() == "publish") seen[s->time_ns()] = {s->fps_out(), stage.ms()};
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  double fps = 0, publish = 0;
  for (const auto& [time, v] : seen) {
    fps += v.first / double(seen.size());
    publish += v.second / double(seen.size());
  }
  return {fps, publish};
}

TEST_F(ReliabilityTest, EightSubscribersCostTheServerLittle) {
  BackgroundProcess server(server_command(), dir_.path() / "server.log");
  // Subscribers that receive but do not decode: on this 2-core machine eight decoders would
  // measure their own CPU use, not what the server pays for them (on a robot they run elsewhere).
  std::vector<std::unique_ptr<dds::StreamSubscriber>> subscribers;
  const auto load_with = [&](int n) {
    while (int(subscribers.size()) < n) {
      subscribers.push_back(std::make_unique<dds::StreamSubscriber>(participant_options(), "live",
                                                                    dds::StreamCallbacks{}));
    }
    for (const auto& s : subscribers) {
      for (int i = 0; i < 600 && s->frames_received() == 0; ++i)
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
      EXPECT_GT(s->frames_received(), 0u) << server.log();
    }
    std::this_thread::sleep_for(std::chrono::seconds(2));  // status windows with all of them
    return server_load(*subscribers.front(), 6);
  };
  const auto [fps1, publish1] = load_with(1);
  const auto [fps8, publish8] = load_with(8);
  std::printf("1 subscriber: %.2f fps out, publish %.3f ms; 8 subscribers: %.2f fps, %.3f ms\n",
              fps1, publish1, fps8, publish8);
  EXPECT_GT(fps8, 0.8 * fps1);
  // Publishing (asynchronous: write() queues the sample) takes well under a millisecond of the
  // 200 ms frame period, and one subscriber alone measured anywhere from 0.18 to 0.48 ms here:
  // 20 % of that is below the jitter of this shared 2-core machine, so the bound is 20 % or
  // 0.5 ms, whichever is larger.
  EXPECT_LT(publish8, std::max(1.2 * publish1, publish1 + 0.5));
}

// Polls the server's status through `subscriber` until its state is `state`, up to `seconds`.
bool server_state_becomes(const client::RgbdSubscriber& subscriber, const std::string& state,
                          double seconds) {
  const auto start = Clock::now();
  while (seconds_since(start) < seconds) {
    if (const auto s = subscriber.status(); s && s->state() == state) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  return false;
}

TEST_F(ReliabilityTest, StalledSourceIsReportedThenExitsWhenConfiguredTo) {
  // The dataset is read frame by frame from disk: moving it away stalls the source.
  const std::filesystem::path data = dir_.path() / "data", away = dir_.path() / "away";
  client::SubscriberOptions options{.participant = participant_options()};
  client::RgbdSubscriber subscriber(options);
  {
    BackgroundProcess server(server_command(), dir_.path() / "server.log");
    ASSERT_TRUE(subscriber.wait_for_frame(std::chrono::seconds(60))) << server.log();
    ASSERT_TRUE(server_state_becomes(subscriber, "running", 10)) << server.log();
    std::filesystem::rename(data, away);
    EXPECT_TRUE(server_state_becomes(subscriber, "source stalled", 10)) << server.log();
    EXPECT_TRUE(server.running()) << "the server should keep serving: " << server.log();
    EXPECT_NE(server.log().find("source stalled"), std::string::npos) << server.log();
    std::filesystem::rename(away, data);  // the cameras come back
    EXPECT_TRUE(server_state_becomes(subscriber, "running", 15)) << server.log();
    const auto frame = subscriber.wait_for_frame(std::chrono::seconds(30));
    EXPECT_TRUE(frame) << "no frame after the source recovered: " << server.log();
    double seconds = 0;
    EXPECT_EQ(server.stop(SIGTERM, 5, &seconds), 0) << server.log();
  }
  // --exit-on-source-end: a clear message and a non-zero exit instead.
  BackgroundProcess server(server_command(" --exit-on-source-end"), dir_.path() / "server2.log");
  ASSERT_TRUE(subscriber.wait_for_frame(std::chrono::seconds(60))) << server.log();
  std::filesystem::rename(data, away);
  const auto start = Clock::now();
  while (server.running() && seconds_since(start) < 20)
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  ASSERT_FALSE(server.running()) << server.log();
  double seconds = 0;
  EXPECT_NE(server.stop(SIGTERM, 1, &seconds), 0) << server.log();
  EXPECT_NE(server.log().find("no frame of dataset"), std::string::npos) << server.log();
  std::filesystem::rename(away, data);
}

}  // namespace
}  // namespace omnisweep
