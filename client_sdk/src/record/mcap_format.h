// MCAP's byte-level pieces shared by the writer and the reader (https://mcap.dev/spec):
// opcodes, little-endian integers, strings and maps, and a bounds-checked cursor.
#pragma once

#include <cstdint>
#include <cstring>
#include <map>
#include <span>
#include <string>
#include <vector>

#include "omnisweep/record/mcap_writer.h"

namespace omnisweep::record::mcap {

inline constexpr std::uint8_t kMagic[8] = {0x89, 'M', 'C', 'A', 'P', '0', '\r', '\n'};

enum Op : std::uint8_t {
  kHeader = 0x01,
  kFooter = 0x02,
  kSchema = 0x03,
  kChannel = 0x04,
  kMessage = 0x05,
  kChunk = 0x06,
  kMessageIndex = 0x07,
  kChunkIndex = 0x08,
  kStatistics = 0x0B,
  kSummaryOffset = 0x0E,
  kDataEnd = 0x0F,
};

// Appends little-endian fields to a byte vector.
class Bytes {
 public:
  template <typename T>
  Bytes& put(T value) {
    for (std::size_t i = 0; i < sizeof(T); ++i)
      out.push_back(std::uint8_t(std::uint64_t(value) >> (8 * i)));
    return *this;
  }
  Bytes& put_bytes(std::span<const std::uint8_t> data) {
    out.insert(out.end(), data.begin(), data.end());
    return *this;
  }
  Bytes& put_string(const std::string& s) {
    put(std::uint32_t(s.size()));
    out.insert(out.end(), s.begin(), s.end());
    return *this;
  }
  Bytes& put_string_map(const std::map<std::string, std::string>& m) {
    Bytes inner;
    for (const auto& [k, v] : m) inner.put_string(k).put_string(v);
    put(std::uint32_t(inner.out.size()));
    return put_bytes(inner.out);
  }
  std::vector<std::uint8_t> out;
};

// A record: opcode, uint64 content length, content.
inline std::vector<std::uint8_t> make_record(Op op, const std::vector<std::uint8_t>& content) {
  Bytes r;
  r.put(std::uint8_t(op)).put(std::uint64_t(content.size())).put_bytes(content);
  return std::move(r.out);
}

// Reads fields from a span; every read past the end throws McapError naming `what`.
class Cursor {
 public:
  Cursor(std::span<const std::uint8_t> bytes, std::string what)
      : bytes_(bytes), what_(std::move(what)) {}
  template <typename T>
  T get() {
    need(sizeof(T));
    std::uint64_t v = 0;
    for (std::size_t i = 0; i < sizeof(T); ++i) v |= std::uint64_t(bytes_[pos_ + i]) << (8 * i);
    pos_ += sizeof(T);
    return T(v);
  }
  std::span<const std::uint8_t> take(std::uint64_t n) {
    need(n);
    const auto s = bytes_.subspan(pos_, std::size_t(n));
    pos_ += std::size_t(n);
    return s;
  }
  std::string get_string() {
    const auto s = take(get<std::uint32_t>());
    return std::string(s.begin(), s.end());
  }
  std::map<std::string, std::string> get_string_map() {
    Cursor inner(take(get<std::uint32_t>()), what_);
    std::map<std::string, std::string> m;
    while (inner.remaining() > 0) {
      std::string key = inner.get_string();
      m[key] = inner.get_string();
    }
    return m;
  }
  std::size_t remaining() const { return bytes_.size() - pos_; }
  std::span<const std::uint8_t> rest() const { return bytes_.subspan(pos_); }

 private:
  void need(std::uint64_t n) const {
    if (n > remaining()) throw McapError(what_ + ": a field runs past the end of its record");
  }
  std::span<const std::uint8_t> bytes_;
  std::size_t pos_ = 0;
  std::string what_;
};

}  // namespace omnisweep::record::mcap
