// An omnisweep stream in MCAP (docs/recording.md): one channel per topic
// (<prefix>/description, <prefix>/rgbd, <prefix>/status, and <prefix>/confidence when asked, and
// the ROS 2 topics when asked: RosRecording below),
// each message the DDS sample's own CDR
// serialization with its encapsulation header (message encoding "cdr"), the schema the OMG IDL
// of idl/omnisweep_msgs.idl (schema encoding "omgidl"), as Foxglove reads them. Payloads stay
// as received: the JPEG and distance bytes are not decoded or re-encoded.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "omnisweep/dds/participant.h"
#include "omnisweep/record/mcap_reader.h"
#include "omnisweep/record/mcap_writer.h"
#include "omnisweep/ros2/ros_messages.h"
#include "omnisweep_msgs.h"

namespace omnisweep::record {

// The ROS 2 topics a recording holds beside the stream's (docs/ros2.md, docs/recording.md),
// made from the stream's own messages as omnisweep-server makes them: /tf_static from the
// description, the colour JPEG and compressedDepth (and with `raw` the 32FC1 image and the point
// cloud) from each frame, /diagnostics from each status. As rosbag2 writes MCAP: profile
// "ros2", schemas "ros2msg" (the complete .msg text), messages "cdr", and each channel's
// offered_qos_profiles.
struct RosRecording {
  ros2::RosOptions options;
  bool raw = false;  // also /distance/image_raw (8 MB a 2048x1024 frame) and /points
};

// Thread-safe: DDS listener threads record while a timer calls flush_due.
class StreamRecorder {
 public:
  // `confidence`: also a channel for <prefix>/confidence. `ros`: the ROS 2 topics too.
  StreamRecorder(const std::filesystem::path& path, const std::string& topic_prefix,
                 McapWriterOptions options = {}, bool confidence = false,
                 std::optional<RosRecording> ros = std::nullopt);

  // log_time: when the message arrived here (wall clock, ns).
  void record(const msg::StreamDescription& description, std::uint64_t log_time_ns);
  void record(const msg::RgbdFrame& frame, std::uint64_t log_time_ns);
  void record(const msg::ServerStatus& status, std::uint64_t log_time_ns);
  // Throws McapError when the recorder was made without `confidence`.
  void record(const msg::ConfidenceFrame& confidence, std::uint64_t log_time_ns);
  void flush_due(std::uint64_t now_ns);
  void close();
  McapWriteStats stats() const;

 private:
  template <typename Message>
  void write(dds::TopicKind kind, Message& message, std::uint64_t log_time_ns,
             std::uint64_t publish_time_ns);

  void write_ros(dds::TopicKind kind, const std::vector<std::uint8_t>& cdr,
                 std::uint64_t log_time_ns, std::uint64_t publish_time_ns);

  mutable std::mutex mutex_;
  McapWriter writer_;
  std::optional<RosRecording> ros_;
  std::unique_ptr<ros2::FrameConverter> converter_;  // with ros_; under mutex_
  std::array<std::optional<std::uint16_t>, dds::kTopics.size()> channels_{};
  std::array<std::uint32_t, dds::kTopics.size()> sequences_{};
};

// The topic a channel of a recording carries (by its schema name), if it is one of ours.
std::optional<dds::TopicKind> recorded_topic(const McapReader& reader, const McapChannel& channel);
// The topic prefix of a recorded channel ("site/a" for "site/a/rgbd").
std::string recorded_prefix(const McapChannel& channel);
// The ROS 2 topic a channel carries (a "ros2msg" schema of ours and a topic that ends as one of
// kTopics' ROS topics), if it is one.
std::optional<dds::TopicKind> recorded_ros_topic(const McapReader& reader,
                                                 const McapChannel& channel);
// The ROS namespace of a recorded namespaced ROS topic ("/site/a" for
// "/site/a/color/image_raw/compressed"; "/" at the root).
std::string recorded_ros_namespace(const McapChannel& channel, dds::TopicKind kind);

// Decodes a recorded CDR message; throws McapError naming the type when it does not parse.
void decode_message(std::span<const std::uint8_t> data, msg::StreamDescription& out);
void decode_message(std::span<const std::uint8_t> data, msg::RgbdFrame& out);
void decode_message(std::span<const std::uint8_t> data, msg::ServerStatus& out);
void decode_message(std::span<const std::uint8_t> data, msg::ConfidenceFrame& out);

}  // namespace omnisweep::record
