// omnisweep-record and omnisweep-play as users run them, with the client SDK's subscriber in
// this process: a recording replays the same frames in order; a recorder killed with SIGKILL
// leaves a file that reads back, missing at most its last second; Foxglove's MCAP reader
// (@mcap/core, tests/mcap/list_channels.mjs) lists the channels and counts we wrote.
#include <gtest/gtest.h>

#include <csignal>
#include <map>
#include <mutex>
#include <regex>
#include <set>
#include <thread>

#include "omnisweep/client/rgbd_subscriber.h"
#include "omnisweep/record/stream_recording.h"
#include "omnisweep/time/clock.h"
#include "tests/support/stream_fixture.h"

namespace omnisweep {
namespace {

namespace fs = std::filesystem;
using testing::BackgroundProcess;
using testing::run_command;

struct RecordedFrame {
  std::uint64_t sequence, log_time_ns;
  std::string color;  // payload bytes
};

std::vector<RecordedFrame> recorded_frames(const fs::path& file, record::McapReadSummary* summary,
                                           std::map<std::string, std::uint64_t>* counts = nullptr) {
  record::McapReader reader(file);
  std::vector<RecordedFrame> frames;
  msg::RgbdFrame frame;
  *summary = reader.read([&](const record::McapMessage& m) {
    const auto kind = record::recorded_topic(reader, *m.channel);
    if (counts) ++(*counts)[m.channel->topic];
    if (kind == dds::TopicKind::kFrames) {
      record::decode_message(m.data, frame);
      frames.push_back({frame.sequence_number(), m.log_time_ns,
                        std::string(frame.color().data().begin(), frame.color().data().end())});
    }
    return true;
  });
  return frames;
}

class RecordTest : public testing::StreamTest {
 protected:
  // Serves the test dataset and records `frames` frames of it into `file`.
  void record_from_server(const fs::path& file, int frames) {
    BackgroundProcess server(server_command(), dir_.path() / "server.log");
    std::string out;
    ASSERT_EQ(run_command(tool_command("record", " --frames " + std::to_string(frames) +
                                                     " --output " + file.string()),
                          &out),
              0)
        << out;
  }
};

TEST_F(RecordTest, ReplayDeliversTheRecordedFramesInOrder) {
  const fs::path file = dir_.path() / "stream.mcap";
  record_from_server(file, 6);
  if (HasFatalFailure()) return;
  record::McapReadSummary summary;
  std::map<std::string, std::uint64_t> counts;
  const std::vector<RecordedFrame> recorded = recorded_frames(file, &summary, &counts);
  EXPECT_TRUE(summary.complete);
  ASSERT_EQ(recorded.size(), 6u);
  for (std::size_t i = 1; i < recorded.size(); ++i)
    EXPECT_GT(recorded[i].sequence, recorded[i - 1].sequence);
  EXPECT_GE(counts[topic_prefix_ + "/description"], 1u);

  // Replay into this process's subscriber; frames arrive in the recorded order, byte-identical.
  std::mutex mutex;
  std::vector<std::uint64_t> arrived;
  client::SubscriberOptions options{.participant = participant_options(), .profile = "reliable"};
  client::RgbdSubscriber subscriber(options,
                                    [&](const std::shared_ptr<const client::RgbdFrame>& f) {
                                      const std::lock_guard lock(mutex);
                                      arrived.push_back(f->sequence_number);
                                    });
  EXPECT_EQ(subscriber.state(), client::ConnectionState::kNoServer);
  std::string out;
  ASSERT_EQ(run_command(tool_command("play", " --wait-for-subscribers 1 --rate 4 " + file.string()),
                        &out),
            0)
      << out;
  for (int i = 0; i < 100 && subscriber.stats().frames_decoded < 6; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  const std::lock_guard lock(mutex);
  ASSERT_EQ(arrived.size(), 6u) << out;
  for (std::size_t i = 0; i < 6; ++i) EXPECT_EQ(arrived[i], recorded[i].sequence);
  const auto latest = subscriber.latest_frame();
  ASSERT_TRUE(latest);
  EXPECT_EQ(latest->color_bytes, recorded.back().color.size());
  ASSERT_TRUE(latest->stream) << "the replayed calibration did not reach the subscriber";
  EXPECT_EQ(latest->stream->rig.num_cameras(), 4);
  EXPECT_EQ(subscriber.stats().decode_errors, 0u);
}

TEST_F(RecordTest, KilledRecorderLeavesAReadableFileMissingAtMostOneSecond) {
  const fs::path file = dir_.path() / "killed.mcap";
  BackgroundProcess server(server_command(), dir_.path() / "server.log");
  BackgroundProcess recorder(tool_command("record", " --verbose --output " + file.string()),
                             dir_.path() / "record.log");
  // Until the recorder has logged frames for three seconds.
  const std::uint64_t start = wall_clock_ns();
  std::regex line(R"(recorded frame (\d+) at (\d+))");
  std::map<std::uint64_t, std::uint64_t> logged;  // sequence -> time
  while (wall_clock_ns() - start < 40'000'000'000ull) {
    logged.clear();
    const std::string log = recorder.log();
    for (std::sregex_iterator it(log.begin(), log.end(), line), end; it != end; ++it)
      logged[std::stoull((*it)[1])] = std::stoull((*it)[2]);
    if (!logged.empty() && logged.rbegin()->second - logged.begin()->second > 3'000'000'000ull)
      break;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  ASSERT_GE(logged.size(), 3u) << recorder.log();
  const std::uint64_t killed_at = wall_clock_ns();
  double seconds = 0;
  recorder.stop(SIGKILL, 5, &seconds);

  record::McapReadSummary summary;
  const std::vector<RecordedFrame> frames = recorded_frames(file, &summary);
  EXPECT_FALSE(summary.complete);
  std::set<std::uint64_t> in_file;
  for (const RecordedFrame& f : frames) in_file.insert(f.sequence);
  int older_missing = 0;
  for (const auto& [sequence, time] : logged)
    older_missing += time + 1'000'000'000ull < killed_at && !in_file.count(sequence);
  std::printf("%zu frames logged before SIGKILL, %zu in the file, %d older than 1 s missing\n",
              logged.size(), frames.size(), older_missing);
  EXPECT_EQ(older_missing, 0);
  // At most 5 of the logged frames missing; written so, since logged.size() - 5 wraps round when
  // a slow run (ASan) logs fewer than 5 frames in its three seconds.
  EXPECT_GE(frames.size() + 5, logged.size());
}

TEST_F(RecordTest, FoxgloveReaderListsTheChannelsAndCounts) {
  if (!OMNISWEEP_HAVE_NODE) GTEST_SKIP() << "Node.js was not found when the build was configured";
  const fs::path node_dir = testing::mcap_node_dir();
  ASSERT_TRUE(fs::exists(node_dir / "node_modules/@mcap/core"))
      << "@mcap/core is not installed in " << node_dir
      << " (the mcap_node_setup test runs npm ci there)";
  const fs::path file = dir_.path() / "stream.mcap";
  record_from_server(file, 4);
  if (HasFatalFailure()) return;
  record::McapReadSummary summary;
  std::map<std::string, std::uint64_t> counts;
  recorded_frames(file, &summary, &counts);
  std::string out;
  ASSERT_EQ(
      run_command("node " + (node_dir / "list_channels.mjs").string() + " " + file.string(), &out),
      0)
      << out;
  for (const auto& [topic, n] : counts) {
    const std::string channel = "\"topic\":\"" + topic + "\"";
    const auto at = out.find(channel);
    ASSERT_NE(at, std::string::npos) << out;
    const std::string rest = out.substr(at);
    EXPECT_NE(rest.find("\"statistics\":" + std::to_string(n) + ",\"read\":" + std::to_string(n)),
              std::string::npos)
        << topic << " should have " << n << " messages: " << out;
    EXPECT_NE(rest.find("\"messageEncoding\":\"cdr\""), std::string::npos) << out;
  }
  EXPECT_EQ(counts[topic_prefix_ + "/rgbd"], 4u);
}

}  // namespace
}  // namespace omnisweep
