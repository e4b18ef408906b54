#include "omnisweep/record/mcap_writer.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "omnisweep/codec/codec.h"
#include "src/record/mcap_format.h"

namespace omnisweep::record {

McapWriter::McapWriter(const std::filesystem::path& path, McapWriterOptions options)
    : path_(path), options_(std::move(options)) {
  fd_ = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd_ < 0) throw McapError("cannot create " + path.string() + ": " + std::strerror(errno));
  mcap::Bytes header;
  header.put_string(options_.profile).put_string(options_.library);
  std::vector<std::uint8_t> start(std::begin(mcap::kMagic), std::end(mcap::kMagic));
  const auto record = mcap::make_record(mcap::kHeader, header.out);
  start.insert(start.end(), record.begin(), record.end());
  append(start);
}

McapWriter::~McapWriter() {
  try {
    close();
  } catch (...) {
  }
}

void McapWriter::append(const std::vector<std::uint8_t>& bytes) {
  if (fd_ < 0) throw McapError(path_.string() + " is closed");
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd_, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) throw McapError("writing " + path_.string() + " failed: " + std::strerror(errno));
    done += std::size_t(n);
  }
  offset_ += bytes.size();
  stats_.bytes = offset_;
}

std::uint16_t McapWriter::add_schema(const std::string& name, const std::string& encoding,
                                     std::span<const std::uint8_t> data) {
  const std::uint16_t id = next_schema_++;
  mcap::Bytes content;
  content.put(id)
      .put_string(name)
      .put_string(encoding)
      .put(std::uint32_t(data.size()))
      .put_bytes(data);
  const auto record = mcap::make_record(mcap::kSchema, content.out);
  append(record);
  schema_records_.insert(schema_records_.end(), record.begin(), record.end());
  return id;
}

std::uint16_t McapWriter::add_channel(std::uint16_t schema_id, const std::string& topic,
                                      const std::string& message_encoding,
                                      const std::map<std::string, std::string>& metadata) {
  const std::uint16_t id = next_channel_++;
  mcap::Bytes content;
  content.put(id)
      .put(schema_id)
      .put_string(topic)
      .put_string(message_encoding)
      .put_string_map(metadata);
  const auto record = mcap::make_record(mcap::kChannel, content.out);
  append(record);
  channel_records_.insert(channel_records_.end(), record.begin(), record.end());
  return id;
}

void McapWriter::write(std::uint16_t channel_id, std::uint32_t sequence, std::uint64_t log_time_ns,
                       std::uint64_t publish_time_ns, std::span<const std::uint8_t> data) {
  if (fd_ < 0) throw McapError(path_.string() + " is closed");
  if (channel_id >= next_channel_)
    throw McapError("message on channel " + std::to_string(channel_id) + ", never added");
  if (chunk_.empty()) chunk_start_ = chunk_end_ = log_time_ns;
  chunk_start_ = std::min(chunk_start_, log_time_ns);
  chunk_end_ = std::max(chunk_end_, log_time_ns);
  chunk_index_[channel_id].emplace_back(log_time_ns, chunk_.size());
  mcap::Bytes record;
  record.put(std::uint8_t(mcap::kMessage))
      .put(std::uint64_t(2 + 4 + 8 + 8 + data.size()))
      .put(channel_id)
      .put(sequence)
      .put(log_time_ns)
      .put(publish_time_ns);
  chunk_.insert(chunk_.end(), record.out.begin(), record.out.end());
  chunk_.insert(chunk_.end(), data.begin(), data.end());
  if (stats_.messages == 0) first_time_ = last_time_ = log_time_ns;
  first_time_ = std::min(first_time_, log_time_ns);
  last_time_ = std::max(last_time_, log_time_ns);
  ++stats_.messages;
  ++stats_.channel_messages[channel_id];
  if (chunk_.size() >= options_.chunk_bytes) close_chunk();
}

void McapWriter::flush_due(std::uint64_t now_ns) {
  if (fd_ >= 0 && !chunk_.empty() && now_ns >= chunk_start_ + options_.chunk_max_age_ns)
    close_chunk();
}

void McapWriter::close_chunk() {
  if (chunk_.empty()) return;
  ChunkIndex index{chunk_start_, chunk_end_, offset_, 0, chunk_.size(), {}, 0};
  mcap::Bytes content;
  content.put(chunk_start_)
      .put(chunk_end_)
      .put(std::uint64_t(chunk_.size()))
      .put(codec::checksum(chunk_))
      .put_string("")
      .put(std::uint64_t(chunk_.size()))
      .put_bytes(chunk_);
  std::vector<std::uint8_t> out = mcap::make_record(mcap::kChunk, content.out);
  index.length = out.size();
  for (const auto& [channel, entries] : chunk_index_) {
    index.index_offsets[channel] = offset_ + out.size();
    mcap::Bytes m;
    m.put(channel).put(std::uint32_t(entries.size() * 16));
    for (const auto& [time, position] : entries) m.put(time).put(position);
    const auto record = mcap::make_record(mcap::kMessageIndex, m.out);
    index.index_length += record.size();
    out.insert(out.end(), record.begin(), record.end());
  }
  append(out);  // chunk and its indexes in one write
  chunks_.push_back(std::move(index));
  ++stats_.chunks;
  chunk_.clear();
  chunk_index_.clear();
}

void McapWriter::close() {
  if (fd_ < 0) return;
  close_chunk();
  append(mcap::make_record(mcap::kDataEnd, mcap::Bytes().put(std::uint32_t(0)).out));

  // Summary: schemas, channels, chunk indexes, statistics; each group has a summary offset.
  const std::uint64_t summary_start = offset_;
  std::vector<std::uint8_t> summary;
  std::vector<std::uint8_t> offsets;
  const auto group = [&](mcap::Op op, const std::vector<std::uint8_t>& records) {
    if (records.empty()) return;
    mcap::Bytes o;
    o.put(std::uint8_t(op))
        .put(std::uint64_t(summary_start + summary.size()))
        .put(std::uint64_t(records.size()));
    const auto record = mcap::make_record(mcap::kSummaryOffset, o.out);
    offsets.insert(offsets.end(), record.begin(), record.end());
    summary.insert(summary.end(), records.begin(), records.end());
  };
  group(mcap::kSchema, schema_records_);
  group(mcap::kChannel, channel_records_);
  std::vector<std::uint8_t> chunk_indexes;
  for (const ChunkIndex& c : chunks_) {
    mcap::Bytes content, offsets_map;
    for (const auto& [channel, offset] : c.index_offsets) offsets_map.put(channel).put(offset);
    content.put(c.start_time)
        .put(c.end_time)
        .put(c.offset)
        .put(c.length)
        .put(std::uint32_t(offsets_map.out.size()))
        .put_bytes(offsets_map.out)
        .put(c.index_length)
        .put_string("")
        .put(c.records_size)
        .put(c.records_size);
    const auto record = mcap::make_record(mcap::kChunkIndex, content.out);
    chunk_indexes.insert(chunk_indexes.end(), record.begin(), record.end());
  }
  group(mcap::kChunkIndex, chunk_indexes);
  mcap::Bytes stats, counts;
  for (const auto& [channel, n] : stats_.channel_messages) counts.put(channel).put(n);
  stats.put(stats_.messages)
      .put(std::uint16_t(next_schema_ - 1))
      .put(std::uint32_t(next_channel_))
      .put(std::uint32_t(0))
      .put(std::uint32_t(0))
      .put(std::uint32_t(chunks_.size()))
      .put(first_time_)
      .put(last_time_)
      .put(std::uint32_t(counts.out.size()))
      .put_bytes(counts.out);
  group(mcap::kStatistics, mcap::make_record(mcap::kStatistics, stats.out));

  const std::uint64_t offsets_start = summary_start + summary.size();
  std::vector<std::uint8_t> tail = summary;
  tail.insert(tail.end(), offsets.begin(), offsets.end());
  mcap::Bytes footer;
  footer.put(std::uint8_t(mcap::kFooter))
      .put(std::uint64_t(20))
      .put(summary_start)
      .put(offsets_start);
  tail.insert(tail.end(), footer.out.begin(), footer.out.end());
  const std::uint32_t crc = codec::checksum(tail);  // summary start through summary_offset_start
  mcap::Bytes end;
  end.put(crc).put_bytes(mcap::kMagic);
  tail.insert(tail.end(), end.out.begin(), end.out.end());
  append(tail);
  const int fd = fd_;
  fd_ = -1;
  if (::fsync(fd) != 0 || ::close(fd) != 0)
    throw McapError("closing " + path_.string() + " failed: " + std::strerror(errno));
}

}  // namespace omnisweep::record
