#include "omnisweep/record/stream_recording.h"

#include <cstring>
#include <map>

#include "idl_text.h"
#include "omnisweep/ros2/ros_schema.h"
#include "omnisweep_msgsPubSubTypes.h"

namespace omnisweep::record {
namespace {

using eprosima::fastrtps::rtps::SerializedPayload_t;

template <typename PubSubType, typename Message>
std::vector<std::uint8_t> to_cdr(Message& message) {
  PubSubType type;
  SerializedPayload_t payload(type.getSerializedSizeProvider(&message)());
  if (!type.serialize(&message, &payload))
    throw McapError(std::string("cannot serialise a ") + type.getName());
  return {payload.data, payload.data + payload.length};
}

template <typename PubSubType, typename Message>
void from_cdr(std::span<const std::uint8_t> data, Message& out) {
  PubSubType type;
  if (data.size() < 4 || data.size() > std::uint64_t(1) << 31)
    throw McapError(std::string("recorded ") + type.getName() + " has an impossible size");
  SerializedPayload_t payload(std::uint32_t(data.size()));
  std::memcpy(payload.data, data.data(), data.size());
  payload.length = std::uint32_t(data.size());
  if (!type.deserialize(&payload, &out))
    throw McapError(std::string("recorded ") + type.getName() + " does not parse as CDR");
}

}  // namespace

StreamRecorder::StreamRecorder(const std::filesystem::path& path, const std::string& topic_prefix,
                               McapWriterOptions options, bool confidence,
                               std::optional<RosRecording> ros)
    : writer_(path,
              [&] {
                // rosbag2's profile when the file holds its topics (rosbag2 skips the others).
                if (options.profile.empty()) options.profile = ros ? "ros2" : "x-omnisweep";
                return options;
              }()),
      ros_(std::move(ros)) {
  const std::span<const std::uint8_t> idl(reinterpret_cast<const std::uint8_t*>(kIdlText),
                                          std::strlen(kIdlText));
  for (const dds::TopicSpec& topic : dds::kTopics) {
    if (!dds::is_stream_topic(topic.kind) ||
        (topic.kind == dds::TopicKind::kConfidence && !confidence))
      continue;
    const std::uint16_t schema = writer_.add_schema(std::string(topic.type_name), "omgidl", idl);
    channels_[int(topic.kind)] = writer_.add_channel(
        schema, dds::topic_name(topic_prefix, topic.kind), "cdr", {{"topic_prefix", topic_prefix}});
  }
  if (!ros_) return;
  converter_ = std::make_unique<ros2::FrameConverter>(ros_->options);
  std::map<std::string, std::uint16_t> schemas;  // one per type (two topics carry images)
  for (const dds::TopicSpec& topic : dds::kTopics) {
    if (dds::is_stream_topic(topic.kind)) continue;
    if (!ros_->raw &&
        (topic.kind == dds::TopicKind::kRosDistance || topic.kind == dds::TopicKind::kRosPoints))
      continue;
    const std::string type = ros2::ros_type(topic.kind);
    if (!schemas.count(type)) {
      const std::string text = ros2::message_definition(type);
      schemas[type] = writer_.add_schema(
          type, "ros2msg",
          std::span(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()));
    }
    channels_[int(topic.kind)] = writer_.add_channel(
        schemas[type], ros2::ros_topic(ros_->options.ros_namespace, topic.kind), "cdr",
        {{"offered_qos_profiles", ros2::offered_qos_profiles(topic.kind)}});
  }
}

void StreamRecorder::write_ros(dds::TopicKind kind, const std::vector<std::uint8_t>& cdr,
                               std::uint64_t log_time_ns, std::uint64_t publish_time_ns) {
  // The caller holds mutex_.
  writer_.write(*channels_[int(kind)], sequences_[int(kind)]++, log_time_ns, publish_time_ns, cdr);
}

template <typename Message>
void StreamRecorder::write(dds::TopicKind kind, Message& message, std::uint64_t log_time_ns,
                           std::uint64_t publish_time_ns) {
  std::vector<std::uint8_t> bytes;
  if constexpr (std::is_same_v<Message, msg::StreamDescription>)
    bytes = to_cdr<msg::StreamDescriptionPubSubType>(message);
  else if constexpr (std::is_same_v<Message, msg::RgbdFrame>)
    bytes = to_cdr<msg::RgbdFramePubSubType>(message);
  else if constexpr (std::is_same_v<Message, msg::ConfidenceFrame>)
    bytes = to_cdr<msg::ConfidenceFramePubSubType>(message);
  else
    bytes = to_cdr<msg::ServerStatusPubSubType>(message);
  if (!channels_[int(kind)])
    throw McapError("this recorder was made without a channel for " +
                    std::string(dds::topic_spec(kind).suffix));
  const std::lock_guard lock(mutex_);
  writer_.write(*channels_[int(kind)], sequences_[int(kind)]++, log_time_ns,
                publish_time_ns ? publish_time_ns : log_time_ns, bytes);
}

void StreamRecorder::record(const msg::StreamDescription& description, std::uint64_t log_time_ns) {
  auto copy = description;
  write(dds::TopicKind::kDescription, copy, log_time_ns, log_time_ns);
  if (!ros_) return;
  const Eigen::Vector3d viewpoint(description.viewpoint().x(), description.viewpoint().y(),
                                  description.viewpoint().z());
  const auto cdr = ros2::to_cdr(ros2::static_transforms(
      log_time_ns, ros_->options, ros2::rig_from_cameras(description), viewpoint));
  const std::lock_guard lock(mutex_);
  write_ros(dds::TopicKind::kRosTfStatic, cdr, log_time_ns, log_time_ns);
}

void StreamRecorder::record(const msg::RgbdFrame& frame, std::uint64_t log_time_ns) {
  // The serializer takes a non-const pointer but does not modify the sample.
  write(dds::TopicKind::kFrames, const_cast<msg::RgbdFrame&>(frame), log_time_ns,
        frame.publish_time_ns());
  if (!ros_) return;
  const ros2::FrameInputs inputs = ros2::frame_inputs(frame);
  const std::lock_guard lock(mutex_);
  const ros2::FrameMessages m = converter_->convert(
      inputs,
      {.color = true, .compressed_depth = true, .distance = ros_->raw, .points = ros_->raw});
  // publish_time: the message's header.stamp, the capture time.
  write_ros(dds::TopicKind::kRosColor, ros2::to_cdr(*m.color), log_time_ns, inputs.stamp_ns);
  write_ros(dds::TopicKind::kRosCompressedDepth, ros2::to_cdr(*m.compressed_depth), log_time_ns,
            inputs.stamp_ns);
  if (ros_->raw) {
    write_ros(dds::TopicKind::kRosDistance, ros2::to_cdr(*m.distance), log_time_ns,
              inputs.stamp_ns);
    write_ros(dds::TopicKind::kRosPoints, ros2::to_cdr(*m.points), log_time_ns, inputs.stamp_ns);
  }
}

void StreamRecorder::record(const msg::ServerStatus& status, std::uint64_t log_time_ns) {
  auto copy = status;
  write(dds::TopicKind::kStatus, copy, log_time_ns, status.time_ns());
  if (!ros_) return;
  const auto cdr = ros2::to_cdr(
      ros2::diagnostics(status.time_ns(), "omnisweep-server: " + ros_->options.ros_namespace,
                        ros_->options.frame_prefix, status));
  const std::lock_guard lock(mutex_);
  write_ros(dds::TopicKind::kRosDiagnostics, cdr, log_time_ns, status.time_ns());
}

void StreamRecorder::record(const msg::ConfidenceFrame& confidence, std::uint64_t log_time_ns) {
  write(dds::TopicKind::kConfidence, const_cast<msg::ConfidenceFrame&>(confidence), log_time_ns,
        log_time_ns);
}

void StreamRecorder::flush_due(std::uint64_t now_ns) {
  const std::lock_guard lock(mutex_);
  writer_.flush_due(now_ns);
}

void StreamRecorder::close() {
  const std::lock_guard lock(mutex_);
  writer_.close();
}

McapWriteStats StreamRecorder::stats() const {
  const std::lock_guard lock(mutex_);
  return writer_.stats();
}

std::optional<dds::TopicKind> recorded_topic(const McapReader& reader, const McapChannel& channel) {
  const auto schema = reader.schemas().find(channel.schema_id);
  if (schema == reader.schemas().end() || channel.message_encoding != "cdr") return std::nullopt;
  for (const dds::TopicSpec& topic : dds::kTopics)
    if (dds::is_stream_topic(topic.kind) && schema->second.name == topic.type_name)
      return topic.kind;
  return std::nullopt;
}

std::optional<dds::TopicKind> recorded_ros_topic(const McapReader& reader,
                                                 const McapChannel& channel) {
  const auto schema = reader.schemas().find(channel.schema_id);
  if (schema == reader.schemas().end() || schema->second.encoding != "ros2msg" ||
      channel.message_encoding != "cdr")
    return std::nullopt;
  const auto kind = dds::topic_kind_of("rt" + channel.topic);
  if (!kind || dds::is_stream_topic(*kind) || ros2::ros_type(*kind) != schema->second.name)
    return std::nullopt;
  return kind;
}

std::string recorded_ros_namespace(const McapChannel& channel, dds::TopicKind kind) {
  const std::string_view suffix = dds::topic_spec(kind).suffix;
  if (dds::topic_spec(kind).scope != dds::TopicScope::kRosNamespace ||
      channel.topic.size() <= suffix.size())
    return "/";
  return channel.topic.substr(0, channel.topic.size() - suffix.size());
}

std::string recorded_prefix(const McapChannel& channel) {
  const auto slash = channel.topic.rfind('/');
  return slash == std::string::npos ? std::string() : channel.topic.substr(0, slash);
}

void decode_message(std::span<const std::uint8_t> data, msg::StreamDescription& out) {
  from_cdr<msg::StreamDescriptionPubSubType>(data, out);
}
void decode_message(std::span<const std::uint8_t> data, msg::RgbdFrame& out) {
  from_cdr<msg::RgbdFramePubSubType>(data, out);
}
void decode_message(std::span<const std::uint8_t> data, msg::ServerStatus& out) {
  from_cdr<msg::ServerStatusPubSubType>(data, out);
}
void decode_message(std::span<const std::uint8_t> data, msg::ConfidenceFrame& out) {
  from_cdr<msg::ConfidenceFramePubSubType>(data, out);
}

}  // namespace omnisweep::record
