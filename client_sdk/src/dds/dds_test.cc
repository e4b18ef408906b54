// The DDS endpoints on their own, in one process on this machine's own domain and topic prefix:
// a publisher's messages reach a subscriber on every topic, the calibration reaches a subscriber
// that joins late (TRANSIENT_LOCAL), matching is counted on both ends, a reader leaves only the
// topics it was not asked for alone, and bad options and profiles are errors naming them.
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <condition_variable>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/publisher/qos/DataWriterQos.hpp>
#include <map>
#include <mutex>
#include <thread>

#include "omnisweep/dds/participant.h"
#include "omnisweep/dds/stream_publisher.h"
#include "omnisweep/dds/stream_subscriber.h"
#include "tests/support/test_support.h"

namespace omnisweep::dds {
namespace {

ParticipantOptions options_for_this_test() {
  ParticipantOptions options;
  options.domain = 1 + getpid() % 200;
  options.topic_prefix = "unit" + std::to_string(getpid()) + "/" +
                         ::testing::UnitTest::GetInstance()->current_test_info()->name();
  options.name = "omnisweep-dds-test";
  return options;
}

// Waits up to 60 s (discovery on a loaded machine can take tens of seconds) for `done`.
template <typename F>
bool eventually(F done) {
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (!done()) {
    if (std::chrono::steady_clock::now() > until) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return true;
}

struct Received {
  std::mutex mutex;
  std::vector<std::uint64_t> frames, confidences;
  std::vector<std::string> states;
  std::optional<std::uint32_t> description_revision;
};

StreamCallbacks record_into(Received& r) {
  StreamCallbacks c;
  c.description = [&r](const msg::StreamDescription& m) {
    const std::lock_guard lock(r.mutex);
    r.description_revision = m.revision();
  };
  c.frame = [&r](const msg::RgbdFrame& m) {
    const std::lock_guard lock(r.mutex);
    r.frames.push_back(m.sequence_number());
  };
  c.status = [&r](const msg::ServerStatus& m) {
    const std::lock_guard lock(r.mutex);
    r.states.push_back(m.state());
  };
  c.confidence = [&r](const msg::ConfidenceFrame& m) {
    const std::lock_guard lock(r.mutex);
    r.confidences.push_back(m.sequence_number());
  };
  return c;
}

TEST(DdsEndpoints, EveryTopicReachesTheSubscriberAndALateJoinerGetsTheDescription) {
  const ParticipantOptions options = options_for_this_test();
  StreamPublisher publisher(options, "omnisweep_frames", /*confidence=*/true);
  msg::StreamDescription description;
  description.revision(7);
  publisher.publish(description);  // before any subscriber exists

  Received received;
  StreamSubscriber subscriber(
      options, "reliable", record_into(received),
      {TopicKind::kDescription, TopicKind::kStatus, TopicKind::kFrames, TopicKind::kConfidence});
  ASSERT_TRUE(eventually([&] {
    return publisher.frame_subscribers() == 1 && subscriber.matched_servers() == 1;
  })) << publisher.frame_subscribers()
      << " " << subscriber.matched_servers();
  ASSERT_TRUE(eventually([&] {
    const std::lock_guard lock(received.mutex);
    return received.description_revision.has_value();
  }));
  EXPECT_EQ(*received.description_revision, 7u);
  ASSERT_TRUE(subscriber.description().has_value());
  EXPECT_EQ(subscriber.description()->revision(), 7u);

  for (std::uint64_t i = 0; i < 3; ++i) {
    msg::RgbdFrame frame;
    frame.sequence_number(i);
    publisher.publish(frame);
    msg::ConfidenceFrame confidence;
    confidence.sequence_number(i);
    publisher.publish(confidence);
  }
  msg::ServerStatus status;
  status.state("running");
  publisher.publish(status);
  ASSERT_TRUE(eventually([&] {
    const std::lock_guard lock(received.mutex);
    return received.frames.size() == 3 && received.confidences.size() == 3 &&
           received.states.size() == 1;
  }));
  EXPECT_EQ(received.frames, (std::vector<std::uint64_t>{0, 1, 2}));  // reliable: all, in order
  EXPECT_EQ(received.confidences, (std::vector<std::uint64_t>{0, 1, 2}));
  EXPECT_EQ(received.states[0], "running");
  EXPECT_EQ(subscriber.frames_received(), 3u);
  ASSERT_TRUE(subscriber.status().has_value());
  EXPECT_EQ(subscriber.status()->state(), "running");
}

TEST(DdsEndpoints, AReaderGetsOnlyTheTopicsItAskedFor) {
  const ParticipantOptions options = options_for_this_test();
  StreamPublisher publisher(options, "omnisweep_frames", /*confidence=*/true);
  Received received;
  // A monitoring identity: status only. Its participant makes no frame reader, so the
  // publisher counts no frame subscriber.
  StreamSubscriber monitor(options, "live", record_into(received), {TopicKind::kStatus});
  msg::ServerStatus status;
  status.state("starting");
  ASSERT_TRUE(eventually([&] {
    publisher.publish(status);  // best effort until the reader has matched
    const std::lock_guard lock(received.mutex);
    return !received.states.empty();
  }));
  msg::RgbdFrame frame;
  publisher.publish(frame);
  msg::ConfidenceFrame confidence;
  publisher.publish(confidence);
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  const std::lock_guard lock(received.mutex);
  EXPECT_TRUE(received.frames.empty());
  EXPECT_TRUE(received.confidences.empty());
  EXPECT_EQ(publisher.frame_subscribers(), 0);
}

TEST(DdsEndpoints, APublisherWithoutConfidenceRefusesIt) {
  StreamPublisher publisher(options_for_this_test());
  msg::ConfidenceFrame confidence;
  EXPECT_EQ(testing::error_message<DdsError>([&] { publisher.publish(confidence); }),
            "this publisher was made without the confidence topic");
}

TEST(DdsEndpoints, BadOptionsAndProfilesAreNamed) {
  ParticipantOptions options = options_for_this_test();
  options.domain = 300;
  EXPECT_EQ(testing::error_message<DdsError>([&] { options.check(); }),
            "domain id 300 is outside 0-232");
  options = options_for_this_test();
  options.topic_prefix = "a//b";
  EXPECT_NE(testing::error_message<DdsError>([&] { options.check(); }).find("a//b"),
            std::string::npos);
  options = options_for_this_test();
  options.qos_file = "/nonexistent/qos.xml";
  EXPECT_NE(testing::error_message<DdsError>([&] {
              StreamPublisher p(options);
            }).find("/nonexistent/qos.xml"),
            std::string::npos);
  const std::string message = testing::error_message<DdsError>(
      [&] { StreamSubscriber s(options_for_this_test(), "no_such_profile", {}); });
  EXPECT_NE(message.find("no_such_profile"), std::string::npos) << message;
  EXPECT_EQ(frame_reader_profile("live"), "omnisweep_live");
  EXPECT_EQ(frame_reader_profile("reliable"), "omnisweep_reliable");
  EXPECT_EQ(frame_reader_profile("my_profile"), "my_profile");
}

// A reliable writer repairs a lost packet only once a heartbeat tells the reader what it holds,
// and only while the sample is still in the writer's KEEP_LAST history. Fast DDS's default
// heartbeat period is 3 s, longer than the frame profile's history at 30 frames/s (8 frames:
// 267 ms), so a frame whose first retransmission was lost too came too late: at 20 % loss the
// network fault test lost 1 reliable frame in 4 runs at 30 frames/s. Every reliable writer of a
// periodic topic beats at least twice per history at its rate (frames: 30/s at most; status: 1/s).
// The description and /tf_static keep their last sample until the next, so any period repairs
// them.
TEST(DdsEndpoints, ReliableWritersBeatTwicePerHistory) {
  Participant participant(options_for_this_test());
  const std::map<std::string, double> rate_hz = {
      {"omnisweep_frames", 30}, {"omnisweep_ros2", 30}, {"omnisweep_status", 1}};
  for (const TopicSpec& spec : kTopics) {
    const std::string profile(spec.writer_profile.empty() ? "omnisweep_frames"
                                                          : spec.writer_profile);
    eprosima::fastdds::dds::DataWriterQos qos;
    ASSERT_EQ(participant.publisher().get_datawriter_qos_from_profile(profile, qos),
              eprosima::fastrtps::types::ReturnCode_t::RETCODE_OK)
        << profile;
    ASSERT_EQ(qos.reliability().kind, eprosima::fastdds::dds::RELIABLE_RELIABILITY_QOS) << profile;
    ASSERT_EQ(qos.history().kind, eprosima::fastdds::dds::KEEP_LAST_HISTORY_QOS) << profile;
    const auto rate = rate_hz.find(profile);
    if (rate == rate_hz.end()) {
      EXPECT_TRUE(profile == "omnisweep_description" || profile == "omnisweep_ros2_static")
          << profile << " has no rate here";
      continue;
    }
    const double history_s = qos.history().depth / rate->second;
    const double heartbeat_s = qos.reliable_writer_qos().times.heartbeatPeriod.to_ns() * 1e-9;
    EXPECT_LE(2 * heartbeat_s, history_s)
        << profile << ": heartbeat every " << heartbeat_s << " s, history " << qos.history().depth
        << " samples at " << rate->second << " Hz";
  }
}

}  // namespace
}  // namespace omnisweep::dds
