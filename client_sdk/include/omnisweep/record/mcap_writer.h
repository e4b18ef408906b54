// Writes MCAP files (https://mcap.dev/spec, the container of rosbag2 and Foxglove): messages
// grouped in chunks, each followed by its message indexes, then a summary (schemas, channels,
// chunk indexes, statistics) with summary offsets and the footer when closed.
//
// Written by hand: Debian 12 packages no MCAP library, and the subset a recorder needs (no
// attachments, metadata or chunk compression: our payloads arrive compressed) is small.
//
// Durability: every record goes to the file with write(2) as soon as it is complete, and an open
// chunk is closed once its first message is older than McapWriterOptions::chunk_max_age_ns
// (flush_due), so a recorder killed with SIGKILL leaves a readable file missing at most that much.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

namespace omnisweep::record {

class McapError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct McapWriterOptions {
  std::string profile;                         // Header profile ("" or "x-...")
  std::string library = "omnisweep";           // Header library
  std::uint64_t chunk_bytes = 8u << 20;        // close a chunk at this size...
  std::uint64_t chunk_max_age_ns = 500000000;  // ...or when its first message is this old
};

struct McapWriteStats {
  std::uint64_t messages = 0;
  std::uint64_t chunks = 0;
  std::uint64_t bytes = 0;  // written to the file so far
  std::map<std::uint16_t, std::uint64_t> channel_messages;
};

// Not thread-safe: one writer per thread, or a lock around it.
class McapWriter {
 public:
  // Creates (truncates) `path`; throws McapError naming it.
  explicit McapWriter(const std::filesystem::path& path, McapWriterOptions options = {});
  ~McapWriter();  // close(), errors swallowed
  McapWriter(const McapWriter&) = delete;
  McapWriter& operator=(const McapWriter&) = delete;

  std::uint16_t add_schema(const std::string& name, const std::string& encoding,
                           std::span<const std::uint8_t> data);
  std::uint16_t add_channel(std::uint16_t schema_id, const std::string& topic,
                            const std::string& message_encoding,
                            const std::map<std::string, std::string>& metadata = {});
  void write(std::uint16_t channel_id, std::uint32_t sequence, std::uint64_t log_time_ns,
             std::uint64_t publish_time_ns, std::span<const std::uint8_t> data);
  // Closes the open chunk if its first message was logged chunk_max_age_ns before `now_ns`.
  void flush_due(std::uint64_t now_ns);
  // Writes the last chunk, the summary and the footer. Further writes throw.
  void close();

  const McapWriteStats& stats() const { return stats_; }

 private:
  struct ChunkIndex {
    std::uint64_t start_time, end_time, offset, length, records_size;
    std::map<std::uint16_t, std::uint64_t> index_offsets;
    std::uint64_t index_length;
  };
  void append(const std::vector<std::uint8_t>& bytes);
  void close_chunk();

  std::filesystem::path path_;
  McapWriterOptions options_;
  int fd_ = -1;
  std::uint64_t offset_ = 0;
  std::vector<std::uint8_t> schema_records_, channel_records_;  // copies for the summary
  std::uint16_t next_schema_ = 1, next_channel_ = 0;
  std::vector<std::uint8_t> chunk_;  // records of the open chunk
  std::uint64_t chunk_start_ = 0, chunk_end_ = 0;
  std::map<std::uint16_t, std::vector<std::pair<std::uint64_t, std::uint64_t>>> chunk_index_;
  std::vector<ChunkIndex> chunks_;
  std::uint64_t first_time_ = 0, last_time_ = 0;
  McapWriteStats stats_;
};

}  // namespace omnisweep::record
