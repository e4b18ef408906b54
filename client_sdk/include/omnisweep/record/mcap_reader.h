// Reads MCAP files (mcap_writer.h) from the start, record by record, so a file whose writer was
// killed (no summary, a record cut short at the end) still reads back up to its last complete
// record. Every length is checked against what remains: a malformed file throws McapError
// naming the byte offset, never reads out of bounds. Chunks: uncompressed or zstd.
#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <span>
#include <string>
#include <vector>

#include "omnisweep/record/mcap_writer.h"

namespace omnisweep::record {

struct McapSchema {
  std::uint16_t id = 0;
  std::string name, encoding;
  std::vector<std::uint8_t> data;
};

struct McapChannel {
  std::uint16_t id = 0, schema_id = 0;
  std::string topic, message_encoding;
  std::map<std::string, std::string> metadata;
};

struct McapMessage {
  const McapChannel* channel = nullptr;
  std::uint32_t sequence = 0;
  std::uint64_t log_time_ns = 0, publish_time_ns = 0;
  std::span<const std::uint8_t> data;
};

struct McapReadSummary {
  std::uint64_t messages = 0;
  std::map<std::uint16_t, std::uint64_t> channel_messages;
  std::uint64_t chunks = 0;
  bool complete = false;   // data end, footer and closing magic present
  bool truncated = false;  // ended inside a record (a writer killed mid-write)
};

class McapReader {
 public:
  // Throws McapError when the file cannot be opened or does not start with the MCAP magic.
  explicit McapReader(const std::filesystem::path& path);

  // Calls `visit` for every message in file order until it returns false.
  McapReadSummary read(const std::function<bool(const McapMessage&)>& visit);

  // Filled as read() meets them.
  const std::map<std::uint16_t, McapSchema>& schemas() const { return schemas_; }
  const std::map<std::uint16_t, McapChannel>& channels() const { return channels_; }

 private:
  // Parses the records in `bytes` (the data section or a chunk's records); false to stop.
  bool parse(std::span<const std::uint8_t> bytes, std::uint64_t base, bool in_chunk,
             McapReadSummary& summary, const std::function<bool(const McapMessage&)>& visit,
             bool* data_end);

  std::filesystem::path path_;
  std::ifstream file_;
  std::uint64_t size_ = 0;
  std::map<std::uint16_t, McapSchema> schemas_;
  std::map<std::uint16_t, McapChannel> channels_;
};

}  // namespace omnisweep::record
