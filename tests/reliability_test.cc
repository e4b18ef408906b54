// Faults on loopback, as a robot's network and power meet them: a server killed with SIGKILL
// and started again reaches a subscriber that kept running; a subscriber blocked in its
// callback slows neither the server nor another subscriber; eight subscribers cost the server
// little more than one; a source that stalls is reported, and ends the server where configured.
// (ctest label: reliability)
#include <gtest/gtest.h>

#include <atomic>
#include <csignal>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <regex>
#include <thread>
#include <vector>

#include "omnisweep/client/rgbd_subscriber.h"
#include "omnisweep/dds/stream_subscriber.h"
#include "omnisweep/wire/wire.h"
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
  double first_start_s = 0;  // a cold start: the server's process, device and first frame
  {
    const auto started = Clock::now();
    BackgroundProcess server(server_command(), dir_.path() / "server1.log");
    ASSERT_TRUE(subscriber.wait_for_frame(std::chrono::seconds(60))) << server.log();
    first_start_s = seconds_since(started);
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
  std::printf("frames from the restarted server after %.2f s (the first start: %.2f s)\n",
              resumed_s, first_start_s);
  // The subscriber that kept running takes the restarted server as fast as a fresh one takes a
  // server: the killed server's writer, whose lease has not yet run out, must not hold it back. The
  // bound is the first start's time in the same run, so a slow machine (ASan, 2 cores) moves both.
  EXPECT_LT(resumed_s, first_start_s + 3.0);
  for (int i = 0; i < 100 && subscriber.stream_info()->revision == first_revision; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  EXPECT_EQ(subscriber.stream_info()->revision, frame->description_revision)
      << "the restarted server's calibration did not arrive";
  EXPECT_EQ(subscriber.state(), client::ConnectionState::kReceiving);
}

// Frames that reach `subscriber`'s callback per second over `seconds`, counted by `frames`.
double frame_rate(const std::atomic<int>& frames, double seconds) {
  const int before = frames;
  const auto start = Clock::now();
  std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
  return (frames - before) / seconds_since(start);
}

// The server's frames out per second and its mean per-frame work (capture + depth + stitch +
// encode, ms) and publish time (ms), means over `seconds` of its status messages.
struct ServerLoad {
  double fps = 0, work_ms = 0, publish_ms = 0;
  std::size_t statuses = 0;
};

// The server's load from the statuses `status()` returns (a subscriber's newest) for `seconds`.
ServerLoad server_load(const std::function<std::optional<wire::StatusReport>()>& status,
                       double seconds) {
  std::map<std::uint64_t, ServerLoad> seen;  // by status time
  const auto start = Clock::now();
  while (seconds_since(start) < seconds) {
    if (const auto s = status()) {
      ServerLoad load{.fps = s->fps_out};
      for (const auto& [stage, ms] : s->stage_ms)
        (stage == "publish" ? load.publish_ms : load.work_ms) += ms;
      seen[s->time_ns] = load;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  ServerLoad mean{.statuses = seen.size()};
  for (const auto& [time, v] : seen) {
    mean.fps += v.fps / double(seen.size());
    mean.work_ms += v.work_ms / double(seen.size());
    mean.publish_ms += v.publish_ms / double(seen.size());
  }
  return mean;
}

// Wall-clock properties are asserted against a baseline measured in the same run, so they hold on
// a machine of any speed and under load (these tests run serially: tests/CMakeLists.txt); the
// absolute figures are omnisweep-bench's.
TEST_F(ReliabilityTest, BlockedSubscriberSlowsNeitherTheServerNorAnother) {
  BackgroundProcess server(server_command(), dir_.path() / "server.log");
  std::atomic<int> fast_frames{0};
  client::SubscriberOptions options{.participant = participant_options()};
  client::RgbdSubscriber fast(
      options, [&](const std::shared_ptr<const client::RgbdFrame>&) { ++fast_frames; });
  ASSERT_TRUE(fast.wait_for_frame(std::chrono::seconds(60))) << server.log();
  std::this_thread::sleep_for(std::chrono::seconds(1));
  // Baseline: the rate one reader gets from this server on this machine, now.
  const double baseline_fps = frame_rate(fast_frames, 8);
  ASSERT_GT(baseline_fps, 0.0) << server.log();

  // An app stuck in its callback: the second reader's first frame never returns until released.
  std::atomic<int> slow_frames{0};
  std::atomic<bool> release{false};
  auto slow = std::make_unique<client::RgbdSubscriber>(
      options, [&](const std::shared_ptr<const client::RgbdFrame>&) {
        ++slow_frames;
        while (!release) std::this_thread::sleep_for(std::chrono::milliseconds(20));
      });
  for (int i = 0; i < 600 && slow_frames == 0; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  ASSERT_EQ(slow_frames, 1) << server.log();
  const double blocked_fps = frame_rate(fast_frames, 8);
  const ServerLoad server_blocked = server_load([&] { return fast.status(); }, 4);
  const int slow_seen = slow_frames;  // before its callback returns and takes the next frame
  release = true;
  slow.reset();
  std::printf(
      "other reader: %.2f fps alone, %.2f fps beside a blocked reader; server %.2f fps out (mean "
      "of %zu statuses); blocked reader %d frame(s)\n",
      baseline_fps, blocked_fps, server_blocked.fps, server_blocked.statuses, slow_seen);
  // The other reader keeps its own pace and the server keeps publishing (ratios 0.87-0.96 measured
  // with the machine slowed 3-11x by CPU hogs); the blocked reader saw only the frame it is stuck
  // in.
  EXPECT_GT(blocked_fps, 0.7 * baseline_fps);
  ASSERT_GE(server_blocked.statuses, 3u);
  EXPECT_GT(server_blocked.fps, 0.7 * baseline_fps);
  EXPECT_EQ(slow_seen, 1);
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
    return server_load([&] { return wire::from_message(subscribers.front()->status()); }, 8);
  };
  const ServerLoad one = load_with(1), eight = load_with(8);
  std::printf(
      "1 subscriber: %.2f fps out, work %.2f ms, publish %.3f ms; 8 subscribers: %.2f fps, work "
      "%.2f ms, publish %.3f ms\n",
      one.fps, one.work_ms, one.publish_ms, eight.fps, eight.work_ms, eight.publish_ms);
  ASSERT_GE(one.statuses, 4u);
  ASSERT_GE(eight.statuses, 4u);
  // The rate holds (0.77-1.3 of it measured with the machine slowed 3-11x by CPU hogs, which the
  // subscribers here share with the server).
  EXPECT_GT(eight.fps, 0.75 * one.fps);
  // What seven more readers add to publishing (write() queues the sample) is small beside what a
  // frame costs the server to make, measured in the same run: under 5 % of one frame's work
  // (measured unloaded and with the machine slowed 3-11x by CPU hogs: under 0.1 %; the publish
  // time itself varies 0.04-0.8 ms with the scheduler, so it is not compared with itself).
  EXPECT_LT(eight.publish_ms - one.publish_ms, 0.05 * one.work_ms);
}

// Polls the server's status through `subscriber` until its state is `state`, up to `seconds`.
bool server_state_becomes(const client::RgbdSubscriber& subscriber, const std::string& state,
                          double seconds) {
  const auto start = Clock::now();
  while (seconds_since(start) < seconds) {
    if (const auto s = subscriber.status(); s && s->state == state) return true;
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
