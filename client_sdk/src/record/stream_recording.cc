#include "omnisweep/record/stream_recording.h"

#include <cstring>

#include "idl_text.h"
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
                               McapWriterOptions options, bool confidence)
    : writer_(path, [&] {
        if (options.profile.empty()) options.profile = "x-omnisweep";
        return options;
      }()) {
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
}

void StreamRecorder::record(const msg::RgbdFrame& frame, std::uint64_t log_time_ns) {
  // The serializer takes a non-const pointer but does not modify the sample.
  write(dds::TopicKind::kFrames, const_cast<msg::RgbdFrame&>(frame), log_time_ns,
        frame.publish_time_ns());
}

void StreamRecorder::record(const msg::ServerStatus& status, std::uint64_t log_time_ns) {
  auto copy = status;
  write(dds::TopicKind::kStatus, copy, log_time_ns, status.time_ns());
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
