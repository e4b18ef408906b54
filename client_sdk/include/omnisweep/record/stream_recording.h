// An omnisweep stream in MCAP (docs/recording.md): one channel per topic
// (<prefix>/description, <prefix>/rgbd, <prefix>/status, and <prefix>/confidence when asked),
// each message the DDS sample's own CDR
// serialization with its encapsulation header (message encoding "cdr"), the schema the OMG IDL
// of idl/omnisweep_msgs.idl (schema encoding "omgidl"), as Foxglove reads them. Payloads stay
// as received: the JPEG and distance bytes are not decoded or re-encoded.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "omnisweep/dds/participant.h"
#include "omnisweep/record/mcap_reader.h"
#include "omnisweep/record/mcap_writer.h"
#include "omnisweep_msgs.h"

namespace omnisweep::record {

// Thread-safe: DDS listener threads record while a timer calls flush_due.
class StreamRecorder {
 public:
  // `confidence`: also a channel for <prefix>/confidence.
  StreamRecorder(const std::filesystem::path& path, const std::string& topic_prefix,
                 McapWriterOptions options = {}, bool confidence = false);

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

  mutable std::mutex mutex_;
  McapWriter writer_;
  std::array<std::optional<std::uint16_t>, dds::kTopics.size()> channels_{};
  std::array<std::uint32_t, dds::kTopics.size()> sequences_{};
};

// The topic a channel of a recording carries (by its schema name), if it is one of ours.
std::optional<dds::TopicKind> recorded_topic(const McapReader& reader, const McapChannel& channel);
// The topic prefix of a recorded channel ("site/a" for "site/a/rgbd").
std::string recorded_prefix(const McapChannel& channel);

// Decodes a recorded CDR message; throws McapError naming the type when it does not parse.
void decode_message(std::span<const std::uint8_t> data, msg::StreamDescription& out);
void decode_message(std::span<const std::uint8_t> data, msg::RgbdFrame& out);
void decode_message(std::span<const std::uint8_t> data, msg::ServerStatus& out);
void decode_message(std::span<const std::uint8_t> data, msg::ConfidenceFrame& out);

}  // namespace omnisweep::record
