#include "omnisweep/dds/stream_subscriber.h"

#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/subscriber/qos/DataReaderQos.hpp>
#include <fastdds/dds/topic/Topic.hpp>
#include <fastdds/dds/topic/TopicDescription.hpp>

namespace omnisweep::dds {
namespace fdds = eprosima::fastdds::dds;
using ReturnCode_t = eprosima::fastrtps::types::ReturnCode_t;

std::string frame_reader_profile(const std::string& name) {
  if (name == "live" || name == "reliable") return "omnisweep_" + name;
  return name;
}

class StreamSubscriber::Listener final : public fdds::DataReaderListener {
 public:
  explicit Listener(StreamSubscriber& owner) : owner_(owner) {}

  // By topic, not by pointer: Fast DDS may call before create_datareader has returned.
  static TopicKind kind_of(fdds::DataReader* reader) {
    return topic_kind_of(reader->get_topicdescription()->get_name())
        .value_or(TopicKind::kDescription);
  }

  void on_data_available(fdds::DataReader* reader) override {
    fdds::SampleInfo info;
    const TopicKind kind = kind_of(reader);
    if (kind == TopicKind::kFrames) {
      while (reader->take_next_sample(&frame_, &info) == ReturnCode_t::RETCODE_OK) {
        if (!info.valid_data) continue;
        ++owner_.frames_;
        if (owner_.callbacks_.frame) owner_.callbacks_.frame(frame_);
      }
    } else if (kind == TopicKind::kConfidence) {
      while (reader->take_next_sample(&confidence_, &info) == ReturnCode_t::RETCODE_OK) {
        if (info.valid_data && owner_.callbacks_.confidence)
          owner_.callbacks_.confidence(confidence_);
      }
    } else if (kind == TopicKind::kDescription) {
      take_latest(reader, owner_.description_, owner_.callbacks_.description);
    } else {
      take_latest(reader, owner_.status_, owner_.callbacks_.status);
    }
  }

  // Takes every sample, keeps the newest in `latest` and hands each to `callback`.
  template <typename T>
  void take_latest(fdds::DataReader* reader, std::optional<T>& latest,
                   const std::function<void(const T&)>& callback) {
    T sample;
    fdds::SampleInfo info;
    while (reader->take_next_sample(&sample, &info) == ReturnCode_t::RETCODE_OK) {
      if (!info.valid_data) continue;
      {
        const std::lock_guard lock(owner_.mutex_);
        latest = sample;
      }
      if (callback) callback(sample);
    }
  }

  void on_subscription_matched(fdds::DataReader* reader,
                               const fdds::SubscriptionMatchedStatus& status) override {
    if (kind_of(reader) == TopicKind::kFrames) owner_.matched_ = status.current_count;
  }

 private:
  StreamSubscriber& owner_;
  msg::RgbdFrame frame_;  // reused: frames are large
  msg::ConfidenceFrame confidence_;
};

StreamSubscriber::StreamSubscriber(const ParticipantOptions& options,
                                   const std::string& frame_profile, StreamCallbacks callbacks,
                                   std::vector<TopicKind> topics)
    : participant_(std::make_unique<Participant>(options)),
      listener_(std::make_unique<Listener>(*this)),
      callbacks_(std::move(callbacks)) {
  fdds::Subscriber& subscriber = participant_->subscriber();
  for (const TopicKind kind : topics) {
    const TopicSpec& spec = topic_spec(kind);
    const std::string profile = spec.reader_profile.empty() ? frame_reader_profile(frame_profile)
                                                            : std::string(spec.reader_profile);
    fdds::DataReaderQos qos;
    if (subscriber.get_datareader_qos_from_profile(profile, qos) != ReturnCode_t::RETCODE_OK)
      throw DdsError("no data_reader QoS profile \"" + profile + "\"");
    readers_[int(kind)] = subscriber.create_datareader(&participant_->topic(kind), qos,
                                                       listener_.get(), fdds::StatusMask::all());
    if (!readers_[int(kind)]) {
      throw DdsError("cannot create the DDS reader of " + topic_name(options.topic_prefix, kind) +
                     " with profile " + profile +
                     (options.security_dir.empty()
                          ? std::string()
                          : ": the permissions in " + options.security_dir +
                                " do not allow subscribing to it"));
    }
  }
}

StreamSubscriber::~StreamSubscriber() {
  // Readers first, so no callback runs while the members it uses are destroyed.
  for (auto* reader : readers_) {
    if (reader) {
      reader->set_listener(nullptr);
      participant_->subscriber().delete_datareader(reader);
    }
  }
}

std::optional<msg::StreamDescription> StreamSubscriber::description() const {
  const std::lock_guard lock(mutex_);
  return description_;
}

std::optional<msg::ServerStatus> StreamSubscriber::status() const {
  const std::lock_guard lock(mutex_);
  return status_;
}

}  // namespace omnisweep::dds
