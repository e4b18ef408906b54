// omnisweep-record: records a stream (calibration, frames, status) to an MCAP file, payloads as
// received. Chunks close at least every 0.5 s, so a recorder killed with SIGKILL leaves a
// readable file missing at most the last half second (plus one 0.1 s timer tick). Ends after
// --frames N, --duration S, or on SIGINT/SIGTERM, and prints the throughput.
#include <CLI/CLI.hpp>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <thread>

#include "client_sdk/tools/cli_checks.h"
#include "client_sdk/tools/dds_flags.h"
#include "client_sdk/tools/ros2_flags.h"
#include "client_sdk/tools/tool_main.h"
#include "omnisweep/dds/stream_subscriber.h"
#include "omnisweep/record/stream_recording.h"
#include "omnisweep/time/clock.h"

namespace {

using namespace omnisweep;

std::atomic<bool> g_stop{false};
void on_signal(int) { g_stop = true; }

int run(int argc, char** argv) {
  CLI::App app{"Record an omnisweep stream to an MCAP file."};
  dds::ParticipantOptions options;
  options.name = "omnisweep-record";
  std::string output, profile = "reliable";
  std::uint64_t want_frames = 0;
  double duration_s = 0;
  bool verbose = false;
  app.add_option("--output", output, "MCAP file to write (replaced if it exists)")->required();
  tools::add_dds_flags(app, options);
  app.add_option("--profile", profile, "Frame QoS: reliable (every frame, default) or live");
  app.add_option("--frames", want_frames, "Stop after this many frames")
      ->check(tools::not_negative());
  app.add_option("--duration", duration_s, "Stop after this many seconds")
      ->check(CLI::Range(0.0, 1e7));
  bool confidence = false;
  app.add_flag("--confidence", confidence,
               "Record the optional confidence topic too (omnisweep-server --confidence)");
  app.add_flag("--verbose", verbose, "Print every frame as it is recorded (sequence number, time)");
  tools::Ros2Flags ros_flags;
  tools::add_ros2_flags(app, ros_flags,
                        "Record only the stream's own topics (by default the ROS 2 topics too, "
                        "made from the stream: rosbag2's MCAP profile, docs/ros2.md)");
  bool ros_raw = false;
  app.add_flag("--ros2-raw", ros_raw,
               "Also record the ROS 2 32FC1 distance image and point cloud (8 MB and 2 MB a "
               "2048x1024 frame at defaults)");
  CLI11_PARSE(app, argc, argv);
  options.check();
  std::optional<record::RosRecording> ros;
  if (auto ros_options = tools::ros2_options(app, ros_flags, options.topic_prefix))
    ros = record::RosRecording{*ros_options, ros_raw};
  else if (ros_raw)
    throw std::invalid_argument("--ros2-raw records ROS 2 topics; drop --no-ros2 or --ros2-raw");
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);

  record::StreamRecorder recorder(output, options.topic_prefix, {}, confidence, ros);
  std::atomic<std::uint64_t> frames{0};
  dds::StreamCallbacks callbacks;
  callbacks.description = [&](const msg::StreamDescription& d) {
    recorder.record(d, wall_clock_ns());
  };
  callbacks.status = [&](const msg::ServerStatus& s) { recorder.record(s, wall_clock_ns()); };
  callbacks.frame = [&](const msg::RgbdFrame& f) {
    if (want_frames && frames >= want_frames) return;
    const std::uint64_t now = wall_clock_ns();
    recorder.record(f, now);
    ++frames;
    if (verbose) {
      std::printf("recorded frame %llu at %llu\n",
                  static_cast<unsigned long long>(f.sequence_number()),
                  static_cast<unsigned long long>(now));
      std::fflush(stdout);
    }
  };
  std::vector<dds::TopicKind> topics = {dds::TopicKind::kDescription, dds::TopicKind::kStatus,
                                        dds::TopicKind::kFrames};
  if (confidence) {
    callbacks.confidence = [&](const msg::ConfidenceFrame& c) {
      recorder.record(c, wall_clock_ns());
    };
    topics.push_back(dds::TopicKind::kConfidence);
  }
  auto subscriber =
      std::make_unique<dds::StreamSubscriber>(options, profile, std::move(callbacks), topics);
  std::printf("omnisweep-record: recording %s/* on domain %d to %s%s%s\n",
              options.topic_prefix.c_str(), options.domain, output.c_str(),
              ros ? ", with the ROS 2 topics under " : "",
              ros ? ros->options.ros_namespace.c_str() : "");
  std::fflush(stdout);

  const auto start = std::chrono::steady_clock::now();
  auto next_report = start + std::chrono::seconds(1);
  while (!g_stop) {
    if (want_frames && frames >= want_frames) break;
    const auto now = std::chrono::steady_clock::now();
    if (duration_s > 0 && now - start >= std::chrono::duration<double>(duration_s)) break;
    recorder.flush_due(wall_clock_ns());
    if (now >= next_report) {
      next_report += std::chrono::seconds(1);
      const record::McapWriteStats s = recorder.stats();
      std::printf("%llu frames, %llu messages, %.1f MB written\n",
                  static_cast<unsigned long long>(frames.load()),
                  static_cast<unsigned long long>(s.messages), s.bytes * 1e-6);
      std::fflush(stdout);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  subscriber.reset();  // no callback runs past this point
  recorder.close();
  const record::McapWriteStats s = recorder.stats();
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf(
      "summary: %llu frames, %llu messages in %llu chunks, %.1f MB in %.1f s (%.2f MB/s, %.1f "
      "frames/s) "
      "to %s\n",
      static_cast<unsigned long long>(frames.load()), static_cast<unsigned long long>(s.messages),
      static_cast<unsigned long long>(s.chunks), s.bytes * 1e-6, seconds, s.bytes * 1e-6 / seconds,
      double(frames) / seconds, output.c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return omnisweep::tools::run_tool("omnisweep-record", argc, argv, run);
}
