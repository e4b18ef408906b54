// The ROS 2 topics of a stream (docs/ros2.md), written beside the stream's own on the same DDS
// participant: the writers exist from the start (ROS tools list the topics), and a frame topic
// costs nothing until a reader matches it: publish_frame converts only what some reader reads.
#pragma once

#include <Eigen/Core>
#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "omnisweep/codec/codec.h"
#include "omnisweep/dds/participant.h"
#include "omnisweep/geometry/rigid3.h"
#include "omnisweep/image/image.h"
#include "omnisweep/ros2/ros_messages.h"
#include "omnisweep/ros2/ros_options.h"
#include "omnisweep_msgs.h"

namespace eprosima::fastdds::dds {
class DataWriter;
}  // namespace eprosima::fastdds::dds

namespace omnisweep::ros2 {

// Registers the ROS 2 types and makes every ROS topic of kTopics on `participant` under
// `ros_namespace` (dds::Participant::topic(kind) then returns them), for writers and readers.
void add_ros_topics(dds::Participant& participant, const std::string& ros_namespace);

class RosPublisher {
 public:
  // Makes the ROS topics on `participant` and a writer for each (QoS profiles omnisweep_ros2
  // and omnisweep_ros2_static). Throws std::invalid_argument for bad options, dds::DdsError when
  // Fast DDS refuses.
  RosPublisher(dds::Participant& participant, const RosOptions& options);
  ~RosPublisher();
  RosPublisher(const RosPublisher&) = delete;
  RosPublisher& operator=(const RosPublisher&) = delete;

  const RosOptions& options() const { return options_; }
  // Readers matched on a ROS topic now.
  int readers(dds::TopicKind kind) const { return matched_[std::size_t(kind)]; }
  // True when some reader reads one of the frame topics (images, points).
  bool wants_frames() const;

  // /tf_static, once (TRANSIENT_LOCAL: late joiners get it); returns the message.
  tf2_msgs::msg::TFMessage publish_static(std::uint64_t stamp_ns,
                                          const std::vector<Rigid3d>& rig_from_cam,
                                          const Eigen::Vector3d& viewpoint);
  // The frame topics that have readers, and those `also` asks for (a Foxglove client's); returns
  // the messages made. Throws codec::CodecError for a payload that does not decode,
  // dds::DdsError when Fast DDS refuses a sample.
  FrameMessages publish_frame(const FrameInputs& frame, const WantedTopics& also = {});
  // The topics some DDS reader reads now.
  WantedTopics wanted() const;
  // A recorded sample (its CDR bytes, as omnisweep-record wrote them) on its topic. Throws
  // std::invalid_argument when the bytes do not parse as the topic's type.
  void publish_recorded(dds::TopicKind kind, std::span<const std::uint8_t> cdr);
  // /diagnostics (name "omnisweep-server: <namespace>"); returns the message.
  diagnostic_msgs::msg::DiagnosticArray publish_diagnostics(std::uint64_t stamp_ns,
                                                            const msg::ServerStatus& status);

 private:
  class Listener;
  template <typename Message>
  void write(dds::TopicKind kind, Message& message);

  dds::Participant* participant_;
  RosOptions options_;
  std::unique_ptr<Listener> listener_;
  std::array<std::atomic<int>, dds::kTopics.size()> matched_{};
  std::array<eprosima::fastdds::dds::DataWriter*, dds::kTopics.size()> writers_{};
  FrameConverter converter_;
};

}  // namespace omnisweep::ros2
