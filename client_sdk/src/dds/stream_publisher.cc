#include "omnisweep/dds/stream_publisher.h"

#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/DataWriterListener.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/publisher/qos/DataWriterQos.hpp>
#include <fastdds/dds/topic/Topic.hpp>

namespace omnisweep::dds {
namespace fdds = eprosima::fastdds::dds;
using ReturnCode_t = eprosima::fastrtps::types::ReturnCode_t;

class StreamPublisher::Listener final : public fdds::DataWriterListener {
 public:
  explicit Listener(StreamPublisher& owner) : owner_(owner) {}
  void on_publication_matched(fdds::DataWriter* writer,
                              const fdds::PublicationMatchedStatus& status) override {
    // By topic, not by pointer: Fast DDS may call before create_datawriter has returned.
    if (topic_kind_of(writer->get_topic()->get_name()) == TopicKind::kFrames)
      owner_.matched_ = status.current_count;
  }

 private:
  StreamPublisher& owner_;
};

StreamPublisher::StreamPublisher(const dds::ParticipantOptions& options,
                                 const std::string& frame_profile, bool confidence)
    : participant_(std::make_unique<dds::Participant>(options)),
      listener_(std::make_unique<Listener>(*this)) {
  fdds::Publisher& publisher = participant_->publisher();
  for (const TopicSpec& topic : kTopics) {
    const TopicKind kind = topic.kind;
    if (!is_stream_topic(kind) || (kind == TopicKind::kConfidence && !confidence)) continue;
    const std::string profile =
        topic.writer_profile.empty() ? frame_profile : std::string(topic.writer_profile);
    fdds::DataWriterQos qos;
    if (publisher.get_datawriter_qos_from_profile(profile, qos) != ReturnCode_t::RETCODE_OK)
      throw dds::DdsError("no data_writer QoS profile \"" + profile + "\"");
    writers_[int(kind)] = publisher.create_datawriter(
        &participant_->topic(kind), qos, listener_.get(), fdds::StatusMask::publication_matched());
    if (!writers_[int(kind)]) {
      throw dds::DdsError(
          "cannot create the DDS writer of " + dds::topic_name(options.topic_prefix, kind) +
          " with profile " + profile +
          (options.security_dir.empty()
               ? std::string()
               : ": the permissions in " + options.security_dir + " do not allow publishing it"));
    }
  }
}

StreamPublisher::~StreamPublisher() {
  for (auto* writer : writers_) {
    if (writer) {
      writer->set_listener(nullptr);
      participant_->publisher().delete_datawriter(writer);
    }
  }
}

void StreamPublisher::publish(const msg::StreamDescription& description) {
  auto copy = description;
  if (!writers_[int(dds::TopicKind::kDescription)]->write(&copy))
    throw dds::DdsError("writing the stream description failed");
}

void StreamPublisher::publish(msg::RgbdFrame& frame) {
  if (!writers_[int(dds::TopicKind::kFrames)]->write(&frame))
    throw dds::DdsError("writing frame " + std::to_string(frame.sequence_number()) + " failed");
}

void StreamPublisher::publish(msg::ConfidenceFrame& confidence) {
  auto* writer = writers_[int(dds::TopicKind::kConfidence)];
  if (!writer) throw dds::DdsError("this publisher was made without the confidence topic");
  if (!writer->write(&confidence)) {
    throw dds::DdsError("writing the confidence of frame " +
                        std::to_string(confidence.sequence_number()) + " failed");
  }
}

void StreamPublisher::publish(msg::ServerStatus& status) {
  if (!writers_[int(dds::TopicKind::kStatus)]->write(&status))
    throw dds::DdsError("writing the server status failed");
}

}  // namespace omnisweep::dds
