// A stream's publishing end (the server, omnisweep-play): one writer per topic of the stream
// (docs/wire-format.md), QoS from the XML profiles (deploy/qos/omnisweep_qos.xml).
#pragma once

#include <array>
#include <atomic>
#include <memory>
#include <string>

#include "omnisweep/dds/participant.h"
#include "omnisweep_msgs.h"

namespace eprosima::fastdds::dds {
class DataWriter;
}  // namespace eprosima::fastdds::dds

namespace omnisweep::dds {

class StreamPublisher {
 public:
  // `frame_profile`: the data_writer profile of the frame topic (and of the confidence topic).
  // `confidence`: also write <prefix>/confidence (publish(ConfidenceFrame&)); off, its writer is
  // never created, so credentials made before the topic existed still work.
  explicit StreamPublisher(const dds::ParticipantOptions& options,
                           const std::string& frame_profile = "omnisweep_frames",
                           bool confidence = false);
  ~StreamPublisher();
  StreamPublisher(const StreamPublisher&) = delete;
  StreamPublisher& operator=(const StreamPublisher&) = delete;

  // Each throws dds::DdsError when Fast DDS refuses the sample.
  void publish(const msg::StreamDescription& description);
  void publish(msg::RgbdFrame& frame);
  void publish(msg::ServerStatus& status);
  // Throws dds::DdsError when the publisher was made without `confidence`, too.
  void publish(msg::ConfidenceFrame& confidence);

  // Readers matched on the frame topic.
  int frame_subscribers() const { return matched_; }
  // The participant it writes on (the ROS 2 topics are written beside the stream's).
  dds::Participant& participant() { return *participant_; }

 private:
  class Listener;
  std::unique_ptr<dds::Participant> participant_;
  std::unique_ptr<Listener> listener_;
  std::atomic<int> matched_{0};
  std::array<eprosima::fastdds::dds::DataWriter*, kTopics.size()> writers_{};
};

}  // namespace omnisweep::dds
