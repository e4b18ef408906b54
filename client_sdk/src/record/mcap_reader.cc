#include "omnisweep/record/mcap_reader.h"

#include <zstd.h>

#include <algorithm>
#include <cstring>

#include "omnisweep/codec/codec.h"
#include "src/record/mcap_format.h"

namespace omnisweep::record {
namespace {

// Chunks larger than this are refused rather than allocated (a corrupt length field).
constexpr std::uint64_t kMaxChunkBytes = 1ull << 32;

std::vector<std::uint8_t> decompress(const std::string& compression,
                                     std::span<const std::uint8_t> records,
                                     std::uint64_t uncompressed_size, const std::string& where) {
  if (compression.empty()) return {records.begin(), records.end()};
  if (compression != "zstd")
    throw McapError(where + ": chunk compression \"" + compression +
                    "\" is not supported (none, zstd)");
  if (uncompressed_size > kMaxChunkBytes) throw McapError(where + ": chunk too large");
  std::vector<std::uint8_t> out(static_cast<std::size_t>(uncompressed_size));
  const std::size_t n = ZSTD_decompress(out.data(), out.size(), records.data(), records.size());
  if (ZSTD_isError(n) || n != out.size())
    throw McapError(where + ": zstd chunk does not decompress to its stated size");
  return out;
}

}  // namespace

McapReader::McapReader(const std::filesystem::path& path) : path_(path) {
  file_.open(path, std::ios::binary);
  if (!file_) throw McapError("cannot open " + path.string());
  std::error_code ec;
  size_ = std::filesystem::file_size(path, ec);
  std::uint8_t magic[8] = {};
  if (ec || size_ < 8 || !file_.read(reinterpret_cast<char*>(magic), 8) ||
      std::memcmp(magic, mcap::kMagic, 8) != 0) {
    throw McapError(path.string() + " is not an MCAP file (no MCAP magic at its start)");
  }
}

bool McapReader::parse(std::span<const std::uint8_t> bytes, std::uint64_t base, bool in_chunk,
                       McapReadSummary& summary,
                       const std::function<bool(const McapMessage&)>& visit, bool* data_end) {
  mcap::Cursor records(bytes, path_.string());
  while (records.remaining() > 0) {
    const std::uint64_t at = base + (bytes.size() - records.remaining());
    const std::string where = path_.string() + " at byte " + std::to_string(at);
    if (records.remaining() < 9) throw McapError(where + ": record header cut short");
    const auto op = records.get<std::uint8_t>();
    const auto length = records.get<std::uint64_t>();
    if (length > records.remaining()) throw McapError(where + ": record runs past its container");
    mcap::Cursor r(records.take(length), where);
    switch (op) {
      case mcap::kSchema: {
        McapSchema s;
        s.id = r.get<std::uint16_t>();
        s.name = r.get_string();
        s.encoding = r.get_string();
        const auto data = r.take(r.get<std::uint32_t>());
        s.data.assign(data.begin(), data.end());
        if (s.id != 0) schemas_[s.id] = std::move(s);
        break;
      }
      case mcap::kChannel: {
        McapChannel c;
        c.id = r.get<std::uint16_t>();
        c.schema_id = r.get<std::uint16_t>();
        c.topic = r.get_string();
        c.message_encoding = r.get_string();
        c.metadata = r.get_string_map();
        channels_[c.id] = std::move(c);
        break;
      }
      case mcap::kMessage: {
        McapMessage m;
        const auto channel = r.get<std::uint16_t>();
        const auto it = channels_.find(channel);
        if (it == channels_.end())
          throw McapError(where + ": message on channel " + std::to_string(channel) +
                          " before its Channel record");
        m.channel = &it->second;
        m.sequence = r.get<std::uint32_t>();
        m.log_time_ns = r.get<std::uint64_t>();
        m.publish_time_ns = r.get<std::uint64_t>();
        m.data = r.rest();
        ++summary.messages;
        ++summary.channel_messages[channel];
        if (!visit(m)) return false;
        break;
      }
      case mcap::kChunk: {
        if (in_chunk) throw McapError(where + ": chunk inside a chunk");
        r.get<std::uint64_t>();  // message start time
        r.get<std::uint64_t>();  // message end time
        const auto uncompressed_size = r.get<std::uint64_t>();
        const auto crc = r.get<std::uint32_t>();
        const std::string compression = r.get_string();
        const auto stored = r.take(r.get<std::uint64_t>());
        const std::vector<std::uint8_t> inner =
            decompress(compression, stored, uncompressed_size, where);
        if (inner.size() != uncompressed_size)
          throw McapError(where + ": chunk size differs from its uncompressed_size");
        if (crc != 0 && codec::checksum(inner) != crc)
          throw McapError(where + ": chunk CRC-32 mismatch");
        ++summary.chunks;
        if (!parse(inner, 0, true, summary, visit, data_end)) return false;
        break;
      }
      case mcap::kDataEnd:
        if (in_chunk) throw McapError(where + ": data end inside a chunk");
        *data_end = true;
        return false;
      case mcap::kHeader:
      case mcap::kFooter:
        throw McapError(where + ": unexpected " + (op == mcap::kHeader ? "header" : "footer"));
      default:
        break;  // message indexes, attachments, metadata, unknown records: skipped
    }
  }
  return true;
}

McapReadSummary McapReader::read(const std::function<bool(const McapMessage&)>& visit) {
  McapReadSummary summary;
  schemas_.clear();
  channels_.clear();
  file_.clear();
  file_.seekg(8);
  std::uint64_t pos = 8;
  std::vector<std::uint8_t> buffer;
  bool data_end = false;
  bool first = true;
  while (pos < size_) {
    const std::string where = path_.string() + " at byte " + std::to_string(pos);
    if (size_ - pos < 9) {
      summary.truncated = true;
      break;
    }
    std::uint8_t head[9];
    file_.read(reinterpret_cast<char*>(head), 9);
    mcap::Cursor c(std::span<const std::uint8_t>(head, 9), where);
    const auto op = c.get<std::uint8_t>();
    const auto length = c.get<std::uint64_t>();
    if (first && op != mcap::kHeader) throw McapError(where + ": the first record is not a header");
    if (length > size_ - pos - 9) {  // cut short: a writer stopped mid-record
      summary.truncated = true;
      break;
    }
    if (op == mcap::kChunk && length > kMaxChunkBytes) throw McapError(where + ": chunk too large");
    buffer.resize(std::size_t(9 + length));
    std::memcpy(buffer.data(), head, 9);
    if (!file_.read(reinterpret_cast<char*>(buffer.data() + 9), std::streamsize(length)))
      throw McapError(where + ": read failed");
    pos += 9 + length;
    if (!first && !parse(buffer, pos - buffer.size(), false, summary, visit, &data_end)) break;
    first = false;
  }
  if (data_end && size_ >= 8 + 9 + 20 + 8) {
    std::uint8_t tail[8];
    file_.clear();
    file_.seekg(std::streamoff(size_ - 8));
    summary.complete =
        file_.read(reinterpret_cast<char*>(tail), 8) && std::memcmp(tail, mcap::kMagic, 8) == 0;
  }
  return summary;
}

}  // namespace omnisweep::record
