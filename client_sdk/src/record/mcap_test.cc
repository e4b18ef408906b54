// The MCAP writer and reader on their own, without the stream recorder: what is written reads
// back (schemas, channels with metadata, messages in order across chunks, the summary), a file
// whose writer never closed reads back to its last closed chunk, a file cut anywhere reads back
// its complete records, and bytes that are not MCAP are errors naming the offset.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <string>
#include <vector>

#include "omnisweep/record/mcap_reader.h"
#include "omnisweep/record/mcap_writer.h"
#include "tests/support/test_support.h"

namespace omnisweep::record {
namespace {

std::vector<std::uint8_t> payload(std::size_t size, std::uint8_t seed) {
  std::vector<std::uint8_t> bytes(size);
  std::iota(bytes.begin(), bytes.end(), seed);
  return bytes;
}

std::vector<std::uint8_t> read_bytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void write_bytes(const std::filesystem::path& path, std::span<const std::uint8_t> bytes) {
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}

McapWriterOptions chunks_of(std::uint64_t bytes, std::uint64_t max_age_ns = 500000000) {
  McapWriterOptions options;
  options.chunk_bytes = bytes;
  options.chunk_max_age_ns = max_age_ns;
  return options;
}

struct Read {
  McapReadSummary summary;
  std::vector<std::string> topics;
  std::vector<std::uint32_t> sequences;
  std::vector<std::vector<std::uint8_t>> data;
};

Read read_all(const std::filesystem::path& path) {
  McapReader reader(path);
  Read r;
  r.summary = reader.read([&](const McapMessage& m) {
    r.topics.push_back(m.channel->topic);
    r.sequences.push_back(m.sequence);
    r.data.emplace_back(m.data.begin(), m.data.end());
    return true;
  });
  return r;
}

// Two channels, 12 messages of 300 bytes; with chunks closed at 1000 bytes, three chunks.
void write_sample(McapWriter& writer) {
  const std::string schema_text = "uint8[] data";
  const auto schema = writer.add_schema(
      "pkg/msg/Blob", "ros2msg",
      {reinterpret_cast<const std::uint8_t*>(schema_text.data()), schema_text.size()});
  const auto a = writer.add_channel(schema, "/a", "cdr", {{"offered_qos_profiles", "x"}});
  const auto b = writer.add_channel(schema, "/b", "cdr");
  for (std::uint32_t i = 0; i < 12; ++i)
    writer.write(i % 2 ? b : a, i, 1000 + i, 900 + i, payload(300, std::uint8_t(i)));
}

TEST(Mcap, WhatIsWrittenReadsBackInOrderAcrossChunks) {
  const testing::ScratchDir dir;
  const auto path = dir.path() / "a.mcap";
  {
    McapWriterOptions options = chunks_of(1000);
    options.profile = "ros2";
    McapWriter writer(path, options);
    write_sample(writer);
    writer.close();
    EXPECT_EQ(writer.stats().messages, 12u);
    // A message record is 331 bytes (9 + 22 + 300): a chunk closes with its 4th, past 1000.
    EXPECT_EQ(writer.stats().chunks, 3u);
    EXPECT_EQ(writer.stats().bytes, std::filesystem::file_size(path));
    EXPECT_THROW(writer.write(0, 99, 1, 1, payload(1, 0)), McapError);  // closed
  }
  McapReader reader(path);
  std::vector<McapMessage> seen;
  std::vector<std::vector<std::uint8_t>> data;
  const McapReadSummary summary = reader.read([&](const McapMessage& m) {
    seen.push_back(m);
    data.emplace_back(m.data.begin(), m.data.end());
    return true;
  });
  EXPECT_TRUE(summary.complete);
  EXPECT_FALSE(summary.truncated);
  EXPECT_EQ(summary.messages, 12u);
  EXPECT_EQ(summary.chunks, 3u);
  ASSERT_EQ(seen.size(), 12u);
  for (std::uint32_t i = 0; i < 12; ++i) {
    EXPECT_EQ(seen[i].sequence, i);
    EXPECT_EQ(seen[i].log_time_ns, 1000u + i);
    EXPECT_EQ(seen[i].publish_time_ns, 900u + i);
    EXPECT_EQ(seen[i].channel->topic, i % 2 ? "/b" : "/a");
    EXPECT_EQ(data[i], payload(300, std::uint8_t(i)));
  }
  ASSERT_EQ(reader.schemas().size(), 1u);
  const McapSchema& schema = reader.schemas().begin()->second;
  EXPECT_EQ(schema.name, "pkg/msg/Blob");
  EXPECT_EQ(schema.encoding, "ros2msg");
  EXPECT_EQ(std::string(schema.data.begin(), schema.data.end()), "uint8[] data");
  ASSERT_EQ(reader.channels().size(), 2u);
  for (const auto& [id, channel] : reader.channels()) {
    EXPECT_EQ(channel.schema_id, schema.id);
    EXPECT_EQ(channel.message_encoding, "cdr");
    if (channel.topic == "/a") {
      EXPECT_EQ(channel.metadata.at("offered_qos_profiles"), "x");
    }
    EXPECT_EQ(summary.channel_messages.at(id), 6u);
  }
}

TEST(Mcap, ReadingStopsWhenTheVisitorSaysSo) {
  const testing::ScratchDir dir;
  const auto path = dir.path() / "a.mcap";
  {
    McapWriter writer(path, chunks_of(1000));
    write_sample(writer);
  }  // the destructor closes
  McapReader reader(path);
  int visited = 0;
  reader.read([&](const McapMessage&) { return ++visited < 5; });
  EXPECT_EQ(visited, 5);
}

TEST(Mcap, AnUnclosedWriterLeavesItsClosedChunksReadable) {
  const testing::ScratchDir dir;
  const auto path = dir.path() / "a.mcap";
  const auto copy = dir.path() / "killed.mcap";
  {
    McapWriter writer(path, chunks_of(1u << 20, 500));
    write_sample(writer);  // one open chunk: nothing of it is in the file yet
    EXPECT_EQ(read_all(path).data.size(), 0u);
    writer.flush_due(1000 + 500);  // the first message (t = 1000) is now 500 ns old
    // What a SIGKILL now would leave: the file as it stands.
    std::filesystem::copy_file(path, copy);
  }
  const Read r = read_all(copy);
  EXPECT_FALSE(r.summary.complete);
  EXPECT_EQ(r.data.size(), 12u);
  EXPECT_EQ(r.data.back(), payload(300, 11));
}

TEST(Mcap, AFileCutAnywhereReadsBackItsCompleteRecords) {
  const testing::ScratchDir dir;
  const auto path = dir.path() / "a.mcap";
  {
    McapWriter writer(path, chunks_of(1000));
    write_sample(writer);
  }
  const std::vector<std::uint8_t> whole = read_bytes(path);
  const auto cut = dir.path() / "cut.mcap";
  std::size_t previous = 0;
  for (std::size_t size = 8; size < whole.size(); size += 97) {
    write_bytes(cut, std::span(whole).first(size));
    const Read r = read_all(cut);
    EXPECT_FALSE(r.summary.complete) << size;
    // Whole chunks only, in order, each message intact; a longer prefix never reads fewer.
    EXPECT_GE(r.data.size(), previous) << size;
    previous = r.data.size();
    for (std::size_t i = 0; i < r.data.size(); ++i)
      EXPECT_EQ(r.data[i], payload(300, std::uint8_t(i))) << size;
  }
  EXPECT_EQ(previous, 12u);  // the last cut lies in the summary, after every message
}

TEST(Mcap, BytesThatAreNotMcapAreErrorsNamingWhere) {
  const testing::ScratchDir dir;
  const auto path = dir.path() / "a.mcap";
  EXPECT_THROW(McapReader(dir.path() / "missing.mcap"), McapError);
  write_bytes(path, payload(64, 0));
  EXPECT_THROW(McapReader{path}, McapError);  // no magic
  {
    McapWriter writer(path, chunks_of(1000));
    write_sample(writer);
  }
  const std::vector<std::uint8_t> whole = read_bytes(path);
  // The first record is not a header.
  std::vector<std::uint8_t> bytes = whole;
  bytes[8] = 0x05;
  write_bytes(path, bytes);
  std::string message = testing::error_message<McapError>([&] { read_all(path); });
  EXPECT_NE(message.find("at byte 8: the first record is not a header"), std::string::npos)
      << message;
  // A flipped bit inside the first message: its chunk's CRC-32 no longer matches.
  bytes = whole;
  const std::vector<std::uint8_t> first = payload(300, 0);
  const auto at = std::search(bytes.begin(), bytes.end(), first.begin(), first.end());
  ASSERT_NE(at, bytes.end());
  at[100] ^= 0x10;
  write_bytes(path, bytes);
  message = testing::error_message<McapError>([&] { read_all(path); });
  EXPECT_NE(message.find("chunk CRC-32 mismatch"), std::string::npos) << message;
  EXPECT_NE(message.find("at byte "), std::string::npos) << message;
}

}  // namespace
}  // namespace omnisweep::record
