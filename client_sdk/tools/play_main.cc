// omnisweep-play: republishes an MCAP recording of omnisweep-record on DDS with its original
// timing (--rate faster or slower, --loop to repeat), to the recorded topic prefix or
// --topic-prefix, and its ROS 2 topics (docs/ros2.md) to the recorded namespace or
// --ros-namespace. --list prints the channels and message counts instead. Frames keep their
// recorded sequence numbers and timestamps.
#include <CLI/CLI.hpp>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <thread>

#include "client_sdk/tools/dds_flags.h"
#include "client_sdk/tools/ros2_flags.h"
#include "client_sdk/tools/tool_main.h"
#include "omnisweep/dds/stream_publisher.h"
#include "omnisweep/foxglove/ros_channels.h"
#include "omnisweep/record/stream_recording.h"
#include "omnisweep/ros2/ros_publisher.h"

namespace {

using namespace omnisweep;
using Clock = std::chrono::steady_clock;

std::atomic<bool> g_stop{false};
void on_signal(int) { g_stop = true; }

int list(const std::string& file) {
  record::McapReader reader(file);
  const record::McapReadSummary summary =
      reader.read([](const record::McapMessage&) { return true; });
  std::printf("%s: %llu messages in %llu chunks, %s\n", file.c_str(),
              static_cast<unsigned long long>(summary.messages),
              static_cast<unsigned long long>(summary.chunks),
              summary.complete    ? "complete"
              : summary.truncated ? "cut short (no summary)"
                                  : "no summary");
  for (const auto& [id, channel] : reader.channels()) {
    const auto n = summary.channel_messages.count(id) ? summary.channel_messages.at(id) : 0;
    const auto schema = reader.schemas().find(channel.schema_id);
    std::printf("  channel %u %s (%s, %s): %llu messages\n", unsigned(id), channel.topic.c_str(),
                schema == reader.schemas().end() ? "no schema" : schema->second.name.c_str(),
                channel.message_encoding.c_str(), static_cast<unsigned long long>(n));
  }
  return 0;
}

int run(int argc, char** argv) {
  CLI::App app{"Republish an omnisweep MCAP recording on DDS."};
  std::string file, frame_profile = "omnisweep_frames";
  dds::ParticipantOptions options;
  options.name = "omnisweep-play";
  options.topic_prefix.clear();
  double rate = 1.0, wait_timeout_s = 10;
  bool loop = false, list_only = false;
  int wait_for = 0;
  app.add_option("file", file, "MCAP file written by omnisweep-record")
      ->required()
      ->check(CLI::ExistingFile);
  tools::add_dds_flags(app, options, "Topic prefix (default: the recorded one)");
  app.add_option("--frame-profile", frame_profile, "data_writer QoS profile of the frame topic");
  app.add_option("--rate", rate, "Playback speed (2 = twice as fast)")
      ->check(CLI::Range(0.01, 1000.0));
  app.add_flag("--loop", loop, "Start again at the end");
  app.add_option("--wait-for-subscribers", wait_for, "Wait for this many frame subscribers first")
      ->check(CLI::Range(0, 1000));
  app.add_option("--wait-timeout", wait_timeout_s, "Give up waiting for subscribers after this (s)")
      ->check(CLI::Range(0.1, 1e6));
  app.add_flag("--list", list_only, "Print the channels and message counts, then exit");
  tools::Ros2Flags ros_flags;
  tools::add_ros2_flags(app, ros_flags,
                        "Do not publish the ROS 2 topics (by default: the recorded ones, or, for a "
                        "recording without them, made from its frames as omnisweep-server does)");
  tools::FoxgloveFlags foxglove_flags;
  tools::add_foxglove_flags(app, foxglove_flags);
  CLI11_PARSE(app, argc, argv);
  if (list_only) return list(file);
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);

  record::McapReader reader(file);
  reader.read([](const record::McapMessage&) { return false; });  // the channels first
  bool confidence = false;  // a recording with the confidence topic replays it too
  std::string recorded_prefix;
  std::optional<std::string> recorded_namespace;  // of recorded ROS 2 topics
  for (const auto& [id, channel] : reader.channels()) {
    if (const auto ros = record::recorded_ros_topic(reader, channel)) {
      if (dds::topic_spec(*ros).scope == dds::TopicScope::kRosNamespace)
        recorded_namespace = record::recorded_ros_namespace(channel, *ros);
      continue;
    }
    const auto kind = record::recorded_topic(reader, channel);
    if (!kind) continue;
    recorded_prefix = record::recorded_prefix(channel);
    confidence = confidence || *kind == dds::TopicKind::kConfidence;
  }
  if (recorded_prefix.empty()) throw std::runtime_error(file + " holds no omnisweep channel");
  if (options.topic_prefix.empty()) options.topic_prefix = recorded_prefix;
  options.check();
  if (recorded_namespace && app.count("--ros-namespace") == 0)
    ros_flags.options.ros_namespace = *recorded_namespace;
  std::optional<ros2::RosOptions> ros_options =
      tools::ros2_options(app, ros_flags, options.topic_prefix);
  const auto fox_options = tools::foxglove_options(app, foxglove_flags, ros_options.has_value());
  dds::StreamPublisher publisher(options, frame_profile, confidence);
  std::unique_ptr<ros2::RosPublisher> ros;
  if (ros_options)
    ros = std::make_unique<ros2::RosPublisher>(publisher.participant(), *ros_options);
  std::unique_ptr<foxglove::FoxgloveServer> fox;
  if (fox_options) {
    fox = std::make_unique<foxglove::FoxgloveServer>(
        *fox_options, foxglove::ros_channels(ros_options->ros_namespace));
    std::printf("omnisweep-play: Foxglove WebSocket server on ws://%s:%d\n",
                fox_options->address.c_str(), fox->port());
  }
  // Recorded ROS topics are replayed as recorded; a recording without them gets them made from
  // its frames, as omnisweep-server makes them.
  const bool derive_ros = ros && !recorded_namespace;
  if (wait_for > 0) {
    const auto deadline = Clock::now() + std::chrono::duration<double>(wait_timeout_s);
    while (publisher.frame_subscribers() < wait_for && Clock::now() < deadline && !g_stop)
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    if (publisher.frame_subscribers() < wait_for) {
      std::fprintf(stderr, "omnisweep-play: %d of %d subscribers after %.1f s\n",
                   publisher.frame_subscribers(), wait_for, wait_timeout_s);
      return 1;
    }
  }
  std::printf("omnisweep-play: %s to %s/* on domain %d at %.2fx\n", file.c_str(),
              options.topic_prefix.c_str(), options.domain, rate);
  std::fflush(stdout);

  std::uint64_t frames = 0;
  do {
    const Clock::time_point start = Clock::now();
    std::uint64_t first_log = 0;
    bool first = true;
    msg::StreamDescription description;
    msg::RgbdFrame frame;
    msg::ServerStatus status;
    msg::ConfidenceFrame frame_confidence;
    const record::McapReadSummary summary = reader.read([&](const record::McapMessage& m) {
      const auto ros_kind = record::recorded_ros_topic(reader, *m.channel);
      const auto kind = ros_kind ? ros_kind : record::recorded_topic(reader, *m.channel);
      if (!kind || (ros_kind && !ros)) return true;
      if (first) first_log = m.log_time_ns, first = false;
      const auto due =
          start + std::chrono::nanoseconds(std::int64_t(double(m.log_time_ns - first_log) / rate));
      while (Clock::now() < due && !g_stop)
        std::this_thread::sleep_until(std::min(due, Clock::now() + std::chrono::milliseconds(50)));
      if (g_stop) return false;
      if (ros_kind) {
        ros->publish_recorded(*ros_kind, m.data);
        if (fox) foxglove::publish(*fox, *ros_kind, m.publish_time_ns, m.data);
      } else if (*kind == dds::TopicKind::kDescription) {
        record::decode_message(m.data, description);
        description.topic_prefix(options.topic_prefix);
        publisher.publish(description);
        if (derive_ros) {
          const auto tf =
              ros->publish_static(m.log_time_ns, ros2::rig_from_cameras(description),
                                  {description.viewpoint().x(), description.viewpoint().y(),
                                   description.viewpoint().z()});
          if (fox)
            foxglove::publish(*fox, dds::TopicKind::kRosTfStatic, m.log_time_ns, ros2::to_cdr(tf));
        }
      } else if (*kind == dds::TopicKind::kFrames) {
        record::decode_message(m.data, frame);
        publisher.publish(frame);
        const ros2::WantedTopics also = fox ? foxglove::wanted(*fox) : ros2::WantedTopics{};
        if (derive_ros && (ros->wants_frames() || also.any())) {
          const auto messages = ros->publish_frame(ros2::frame_inputs(frame), also);
          if (fox) foxglove::publish(*fox, messages);
        }
        ++frames;
      } else if (*kind == dds::TopicKind::kConfidence) {
        record::decode_message(m.data, frame_confidence);
        publisher.publish(frame_confidence);
      } else {
        record::decode_message(m.data, status);
        publisher.publish(status);
        if (derive_ros) {
          const auto diagnostics = ros->publish_diagnostics(status.time_ns(), status);
          if (fox)
            foxglove::publish(*fox, dds::TopicKind::kRosDiagnostics, status.time_ns(),
                              ros2::to_cdr(diagnostics));
        }
      }
      return true;
    });
    if (summary.truncated)
      std::printf(
          "omnisweep-play: the recording was cut short; played its %llu complete messages\n",
          static_cast<unsigned long long>(summary.messages));
  } while (loop && !g_stop);
  // Let reliable readers fetch the last samples before the writers go away.
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  std::printf("summary: %llu frames published\n", static_cast<unsigned long long>(frames));
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return omnisweep::tools::run_tool("omnisweep-play", argc, argv, run);
}
