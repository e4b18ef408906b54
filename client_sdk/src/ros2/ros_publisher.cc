#include "omnisweep/ros2/ros_publisher.h"

#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/DataWriterListener.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/publisher/qos/DataWriterQos.hpp>
#include <fastdds/dds/topic/Topic.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>

#include "omnisweep/ros2/ros_messages.h"
#include "ros2_msgsPubSubTypes.h"

namespace omnisweep::ros2 {
namespace fdds = eprosima::fastdds::dds;
using ReturnCode_t = eprosima::fastrtps::types::ReturnCode_t;
using dds::TopicKind;

namespace {

fdds::TypeSupport ros_type(TopicKind kind) {
  switch (kind) {
    case TopicKind::kRosColor:
    case TopicKind::kRosCompressedDepth:
      return fdds::TypeSupport(new sensor_msgs::msg::CompressedImagePubSubType());
    case TopicKind::kRosDistance:
      return fdds::TypeSupport(new sensor_msgs::msg::ImagePubSubType());
    case TopicKind::kRosPoints:
      return fdds::TypeSupport(new sensor_msgs::msg::PointCloud2PubSubType());
    case TopicKind::kRosTfStatic:
      return fdds::TypeSupport(new tf2_msgs::msg::TFMessagePubSubType());
    case TopicKind::kRosDiagnostics:
      return fdds::TypeSupport(new diagnostic_msgs::msg::DiagnosticArrayPubSubType());
    default:
      break;
  }
  throw dds::DdsError("not a ROS 2 topic: " + std::string(dds::topic_spec(kind).suffix));
}

}  // namespace

void add_ros_topics(dds::Participant& participant, const std::string& ros_namespace) {
  check_namespace(ros_namespace);
  for (const dds::TopicSpec& spec : dds::kTopics) {
    if (!dds::is_stream_topic(spec.kind))
      participant.add_topic(spec.kind, dds::ros_topic_name(ros_namespace, spec.kind),
                            ros_type(spec.kind));
  }
}

class RosPublisher::Listener final : public fdds::DataWriterListener {
 public:
  explicit Listener(RosPublisher& owner) : owner_(owner) {}
  void on_publication_matched(fdds::DataWriter* writer,
                              const fdds::PublicationMatchedStatus& status) override {
    // By topic, not by pointer: Fast DDS may call before create_datawriter has returned.
    if (const auto kind = dds::topic_kind_of(writer->get_topic()->get_name()))
      owner_.matched_[std::size_t(*kind)] = status.current_count;
  }

 private:
  RosPublisher& owner_;
};

RosPublisher::RosPublisher(dds::Participant& participant, const RosOptions& options)
    : participant_(&participant),
      options_(options),
      listener_(std::make_unique<Listener>(*this)),
      converter_(options) {
  options_.check();
  add_ros_topics(participant, options_.ros_namespace);
  fdds::Publisher& publisher = participant.publisher();
  for (const dds::TopicSpec& spec : dds::kTopics) {
    if (dds::is_stream_topic(spec.kind)) continue;
    const std::string name = dds::ros_topic_name(options_.ros_namespace, spec.kind);
    fdds::Topic& topic = participant.topic(spec.kind);
    const std::string profile(spec.writer_profile);
    fdds::DataWriterQos qos;
    if (publisher.get_datawriter_qos_from_profile(profile, qos) != ReturnCode_t::RETCODE_OK)
      throw dds::DdsError("no data_writer QoS profile \"" + profile + "\"");
    writers_[std::size_t(spec.kind)] = publisher.create_datawriter(
        &topic, qos, listener_.get(), fdds::StatusMask::publication_matched());
    if (!writers_[std::size_t(spec.kind)]) {
      throw dds::DdsError("cannot create the DDS writer of " + name + " with profile " + profile +
                          (participant.options().security_dir.empty()
                               ? std::string()
                               : ": the permissions in " + participant.options().security_dir +
                                     " do not allow publishing it (make the credentials again "
                                     "with deploy/security/make-credentials.sh, or give "
                                     "--no-ros2)"));
    }
  }
}

RosPublisher::~RosPublisher() {
  for (auto* writer : writers_) {
    if (writer) {
      writer->set_listener(nullptr);
      participant_->publisher().delete_datawriter(writer);
    }
  }
}

bool RosPublisher::wants_frames() const { return wanted().any(); }

template <typename Message>
void RosPublisher::write(TopicKind kind, Message& message) {
  if (!writers_[std::size_t(kind)]->write(&message)) {
    throw dds::DdsError("writing " + dds::ros_topic_name(options_.ros_namespace, kind) + " failed");
  }
}

tf2_msgs::msg::TFMessage RosPublisher::publish_static(std::uint64_t stamp_ns,
                                                      const std::vector<Rigid3d>& rig_from_cam,
                                                      const Eigen::Vector3d& viewpoint) {
  tf2_msgs::msg::TFMessage m = static_transforms(stamp_ns, options_, rig_from_cam, viewpoint);
  write(TopicKind::kRosTfStatic, m);
  return m;
}

WantedTopics RosPublisher::wanted() const {
  return {readers(TopicKind::kRosColor) > 0, readers(TopicKind::kRosCompressedDepth) > 0,
          readers(TopicKind::kRosDistance) > 0, readers(TopicKind::kRosPoints) > 0};
}

FrameMessages RosPublisher::publish_frame(const FrameInputs& frame, const WantedTopics& also) {
  const WantedTopics dds = wanted();
  FrameMessages m = converter_.convert(frame, dds | also);
  if (dds.color) write(TopicKind::kRosColor, *m.color);
  if (dds.compressed_depth) write(TopicKind::kRosCompressedDepth, *m.compressed_depth);
  if (dds.distance) write(TopicKind::kRosDistance, *m.distance);
  if (dds.points) write(TopicKind::kRosPoints, *m.points);
  return m;
}

void RosPublisher::publish_recorded(TopicKind kind, std::span<const std::uint8_t> cdr) {
  const auto replay = [&]<typename Message>(Message message) { write(kind, message); };
  switch (kind) {
    case TopicKind::kRosColor:
    case TopicKind::kRosCompressedDepth:
      return replay(from_cdr<sensor_msgs::msg::CompressedImage>(cdr));
    case TopicKind::kRosDistance:
      return replay(from_cdr<sensor_msgs::msg::Image>(cdr));
    case TopicKind::kRosPoints:
      return replay(from_cdr<sensor_msgs::msg::PointCloud2>(cdr));
    case TopicKind::kRosTfStatic:
      return replay(from_cdr<tf2_msgs::msg::TFMessage>(cdr));
    case TopicKind::kRosDiagnostics:
      return replay(from_cdr<diagnostic_msgs::msg::DiagnosticArray>(cdr));
    default:
      throw std::invalid_argument("not a ROS 2 topic: " +
                                  std::string(dds::topic_spec(kind).suffix));
  }
}

diagnostic_msgs::msg::DiagnosticArray RosPublisher::publish_diagnostics(
    std::uint64_t stamp_ns, const msg::ServerStatus& status) {
  auto m = diagnostics(stamp_ns, "omnisweep-server: " + options_.ros_namespace,
                       options_.frame_prefix, status);
  write(TopicKind::kRosDiagnostics, m);
  return m;
}

}  // namespace omnisweep::ros2
