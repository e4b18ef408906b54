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

constexpr TopicKind kFrameTopics[] = {TopicKind::kRosColor, TopicKind::kRosCompressedDepth,
                                      TopicKind::kRosDistance, TopicKind::kRosPoints};

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
      distance_codec_(codec::make_distance_codec("qinv16-zstd")),
      color_codec_(codec::make_color_codec("jpeg")) {
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

bool RosPublisher::wants_frames() const {
  for (const TopicKind kind : kFrameTopics)
    if (readers(kind) > 0) return true;
  return false;
}

template <typename Message>
void RosPublisher::write(TopicKind kind, Message& message) {
  if (!writers_[std::size_t(kind)]->write(&message)) {
    throw dds::DdsError("writing " + dds::ros_topic_name(options_.ros_namespace, kind) + " failed");
  }
}

void RosPublisher::publish_static(std::uint64_t stamp_ns, const std::vector<Rigid3d>& rig_from_cam,
                                  const Eigen::Vector3d& viewpoint) {
  tf2_msgs::msg::TFMessage m = static_transforms(stamp_ns, options_, rig_from_cam, viewpoint);
  write(TopicKind::kRosTfStatic, m);
}

void RosPublisher::publish_frame(const FrameInputs& frame) {
  const bool color = readers(TopicKind::kRosColor) > 0;
  const bool depth = readers(TopicKind::kRosCompressedDepth) > 0;
  const bool distance = readers(TopicKind::kRosDistance) > 0;
  const bool points = readers(TopicKind::kRosPoints) > 0;
  if (color) {
    auto m = compressed_color(make_header(frame.stamp_ns, options_.panorama_frame()), frame.jpeg);
    write(TopicKind::kRosColor, m);
  }
  if (!depth && !distance && !points) return;
  if (frame.distance_codec != distance_codec_->name())
    distance_codec_ = codec::make_distance_codec(frame.distance_codec);
  // The stream's own levels: compressedDepth carries them losslessly, and the metres of the
  // image and the points are what every subscriber of the stream decodes.
  const Image<std::uint16_t> levels = distance_codec_->decode_levels(
      frame.distance, frame.width, frame.height, frame.distance_params);
  if (depth) {
    auto m = compressed_depth(make_header(frame.stamp_ns, options_.panorama_frame()), levels,
                              frame.distance_params);
    write(TopicKind::kRosCompressedDepth, m);
  }
  if (!distance && !points) return;
  const FloatImage metres =
      distance_codec_->decode(frame.distance, frame.width, frame.height, frame.distance_params);
  if (distance) {
    auto m = distance_image(make_header(frame.stamp_ns, options_.panorama_frame()), metres);
    write(TopicKind::kRosDistance, m);
  }
  if (points) {
    Rgb8Image decoded;
    const Rgb8Image* rgb = frame.color;
    if (!rgb) {
      decoded = color_codec_->decode(frame.jpeg, frame.width, frame.height);
      rgb = &decoded;
    }
    auto m = point_cloud(make_header(frame.stamp_ns, options_.rig_frame()), metres, *rgb,
                         frame.viewpoint, options_.points_width, options_.points_height);
    write(TopicKind::kRosPoints, m);
  }
}

void RosPublisher::publish_diagnostics(std::uint64_t stamp_ns, const msg::ServerStatus& status) {
  auto m = diagnostics(stamp_ns, "omnisweep-server: " + options_.ros_namespace,
                       options_.frame_prefix, status);
  write(TopicKind::kRosDiagnostics, m);
}

}  // namespace omnisweep::ros2
