// The stream recorder and reader on their own, without DDS: what goes in comes back by topic,
// and the optional confidence channel exists only when asked for.
#include "omnisweep/record/stream_recording.h"

#include <gtest/gtest.h>

#include <map>

#include "omnisweep/wire/wire.h"
#include "tests/support/test_support.h"

namespace omnisweep::record {
namespace {

msg::ConfidenceFrame confidence_message(std::uint64_t sequence) {
  Gray8Image levels(16, 8);
  for (std::size_t i = 0; i < levels.size(); ++i) levels.data()[i] = std::uint8_t(i * 3 + sequence);
  msg::ConfidenceFrame c;
  c.sequence_number(sequence);
  c.description_revision(5);
  c.width(16);
  c.height(8);
  c.confidence(wire::make_payload(
      codec::kConf8Zstd, codec::make_confidence_codec(codec::kConf8Zstd)->encode(levels, 1)));
  return c;
}

TEST(StreamRecording, ConfidenceChannelRoundTrips) {
  const testing::ScratchDir dir;
  const auto path = dir.path() / "stream.mcap";
  {
    StreamRecorder recorder(path, "site/a", {}, /*confidence=*/true);
    msg::StreamDescription description;
    description.revision(5);
    recorder.record(description, 1'000);
    for (std::uint64_t i = 0; i < 3; ++i) {
      recorder.record(confidence_message(i), 2'000 + i);
      msg::RgbdFrame frame;
      frame.sequence_number(i);
      recorder.record(frame, 2'000 + i);
    }
    recorder.close();
  }
  McapReader reader(path);
  std::map<dds::TopicKind, int> counts;
  std::vector<std::uint64_t> confidence_sequences;
  reader.read([&](const McapMessage& m) {
    const auto kind = recorded_topic(reader, *m.channel);
    EXPECT_TRUE(kind) << m.channel->topic;
    if (!kind) return true;
    ++counts[*kind];
    EXPECT_EQ(recorded_prefix(*m.channel), "site/a");
    if (*kind == dds::TopicKind::kConfidence) {
      msg::ConfidenceFrame c;
      decode_message(m.data, c);
      confidence_sequences.push_back(c.sequence_number());
      const Gray8Image levels = wire::decode_confidence(c, 16, 8);
      EXPECT_EQ(levels.data()[1], std::uint8_t(3 + c.sequence_number()));
      EXPECT_EQ(m.channel->topic, "site/a/confidence");
    }
    return true;
  });
  EXPECT_EQ(counts[dds::TopicKind::kDescription], 1);
  EXPECT_EQ(counts[dds::TopicKind::kFrames], 3);
  EXPECT_EQ(counts[dds::TopicKind::kConfidence], 3);
  EXPECT_EQ(confidence_sequences, (std::vector<std::uint64_t>{0, 1, 2}));
}

TEST(StreamRecording, WithoutConfidenceThereIsNoChannelForIt) {
  const testing::ScratchDir dir;
  const auto path = dir.path() / "plain.mcap";
  {
    StreamRecorder recorder(path, "plain");
    EXPECT_THROW(recorder.record(confidence_message(0), 1), McapError);
    recorder.close();
  }
  McapReader reader(path);
  reader.read([](const McapMessage&) { return false; });
  EXPECT_EQ(reader.channels().size(), 3u);
  for (const auto& [id, channel] : reader.channels())
    EXPECT_NE(recorded_topic(reader, channel), dds::TopicKind::kConfidence);
}

}  // namespace
}  // namespace omnisweep::record
