// A DDS domain participant with omnisweep's types registered and its QoS profiles loaded: what
// the server's publisher and the SDK's subscriber stand on. One RAII owner per participant, as
// in Fast DDS's examples: the constructor builds participant -> types -> topics and throws
// DdsError naming the entity that failed; the destructor deletes the contained entities, then
// the participant.
//
// Topics (docs/wire-format.md): kTopics below, the one list of them.
// QoS comes from Fast DDS XML profiles (deploy/qos/omnisweep_qos.xml, embedded at build time;
// ParticipantOptions::qos_file loads another file instead).
#pragma once

#include <array>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>

namespace eprosima::fastdds::dds {
class DomainParticipant;
class Publisher;
class Subscriber;
class Topic;
class TypeSupport;
}  // namespace eprosima::fastdds::dds

namespace omnisweep::dds {

class DdsError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

enum class TopicKind {
  kDescription,
  kFrames,
  kStatus,
  kConfidence,
  // ROS 2 topics (docs/ros2.md; their types and writers are omnisweep::ros2's).
  kRosColor,
  kRosCompressedDepth,
  kRosDistance,
  kRosPoints,
  kRosTfStatic,
  kRosDiagnostics,
};

// Where a topic's name comes from: the stream's prefix ("<prefix>/rgbd"), the ROS namespace
// ("rt<namespace>/color/image_raw/compressed", rmw_fastrtps' mapping of a ROS topic), or the
// ROS root ("rt/tf_static").
enum class TopicScope { kStream, kRosNamespace, kRosRoot };

// A topic: its name after the prefix or namespace, its message type (idl/omnisweep_msgs.idl,
// idl/ros2/ros2_msgs.idl) and the QoS profiles of its writer and reader
// (deploy/qos/omnisweep_qos.xml); an empty profile means the frame topic's, which the endpoints
// choose (live or reliable).
struct TopicSpec {
  TopicKind kind;
  TopicScope scope;
  std::string_view suffix;
  std::string_view type_name;
  std::string_view writer_profile;
  std::string_view reader_profile;
};
inline constexpr std::array<TopicSpec, 10> kTopics = {{
    {TopicKind::kDescription, TopicScope::kStream, "/description",
     "omnisweep::msg::StreamDescription", "omnisweep_description", "omnisweep_description"},
    {TopicKind::kFrames, TopicScope::kStream, "/rgbd", "omnisweep::msg::RgbdFrame", "", ""},
    {TopicKind::kStatus, TopicScope::kStream, "/status", "omnisweep::msg::ServerStatus",
     "omnisweep_status", "omnisweep_status"},
    {TopicKind::kConfidence, TopicScope::kStream, "/confidence", "omnisweep::msg::ConfidenceFrame",
     "", ""},
    {TopicKind::kRosColor, TopicScope::kRosNamespace, "/color/image_raw/compressed",
     "sensor_msgs::msg::dds_::CompressedImage_", "omnisweep_ros2", "omnisweep_ros2"},
    {TopicKind::kRosCompressedDepth, TopicScope::kRosNamespace,
     "/distance/image_raw/compressedDepth", "sensor_msgs::msg::dds_::CompressedImage_",
     "omnisweep_ros2", "omnisweep_ros2"},
    {TopicKind::kRosDistance, TopicScope::kRosNamespace, "/distance/image_raw",
     "sensor_msgs::msg::dds_::Image_", "omnisweep_ros2", "omnisweep_ros2"},
    {TopicKind::kRosPoints, TopicScope::kRosNamespace, "/points",
     "sensor_msgs::msg::dds_::PointCloud2_", "omnisweep_ros2", "omnisweep_ros2"},
    {TopicKind::kRosTfStatic, TopicScope::kRosRoot, "/tf_static", "tf2_msgs::msg::dds_::TFMessage_",
     "omnisweep_ros2_static", "omnisweep_ros2_static"},
    {TopicKind::kRosDiagnostics, TopicScope::kRosRoot, "/diagnostics",
     "diagnostic_msgs::msg::dds_::DiagnosticArray_", "omnisweep_ros2", "omnisweep_ros2"},
}};
constexpr const TopicSpec& topic_spec(TopicKind kind) { return kTopics[std::size_t(kind)]; }
static_assert(topic_spec(TopicKind::kRosDiagnostics).kind == TopicKind::kRosDiagnostics,
              "kTopics is in TopicKind's order");
constexpr bool is_stream_topic(TopicKind kind) {
  return topic_spec(kind).scope == TopicScope::kStream;
}

// A stream topic's name: "<prefix>/description", "<prefix>/rgbd", ...
std::string topic_name(const std::string& prefix, TopicKind kind);
// A ROS 2 topic's DDS name: "rt<ros_namespace><suffix>" or "rt<suffix>" (kRosRoot); the
// namespace is a valid ROS name (omnisweep::ros2::check_namespace), "/" for none.
std::string ros_topic_name(const std::string& ros_namespace, TopicKind kind);
// The kind of a full DDS topic name, by its suffix (and "rt/" for ROS topics); nullopt for none.
std::optional<TopicKind> topic_kind_of(std::string_view name);

struct ParticipantOptions {
  int domain = 0;  // DDS domain id, 0-232 (the range Fast DDS's default port mapping allows)
  std::string topic_prefix = "omnisweep";  // letters, digits, '_', '-', '/' between words
  std::string qos_file;                    // empty: the embedded deploy/qos/omnisweep_qos.xml
  std::string name = "omnisweep";          // participant name, shown by DDS tools
  // DDS Security: a folder made by deploy/security/make-credentials.sh (identity_ca.pem,
  // cert.pem, key.pem, permissions_ca.pem, governance.p7s, permissions.p7s). Turns on
  // authentication (PKI-DH), encryption (AES-GCM-GMAC) and access control per topic. Empty: none
  // (or whatever the QoS file's omnisweep_participant profile sets).
  std::string security_dir;

  // Throws DdsError naming the bad option.
  void check() const;
};

class Participant {
 public:
  explicit Participant(const ParticipantOptions& options);
  ~Participant();
  Participant(const Participant&) = delete;
  Participant& operator=(const Participant&) = delete;

  const ParticipantOptions& options() const { return options_; }
  eprosima::fastdds::dds::DomainParticipant& participant() const { return *participant_; }
  // The topic of `kind`: the stream's are made by the constructor, a ROS 2 topic by add_topic.
  // Throws DdsError for a topic not made.
  eprosima::fastdds::dds::Topic& topic(TopicKind kind) const;
  // Registers `type` (kTopics' type name for `kind`) and makes the topic `name`, once per kind
  // (a second call returns the first's topic). For the ROS 2 topics, whose types the ros2
  // module owns. Throws DdsError when Fast DDS refuses.
  eprosima::fastdds::dds::Topic& add_topic(TopicKind kind, const std::string& name,
                                           const eprosima::fastdds::dds::TypeSupport& type);
  eprosima::fastdds::dds::Publisher& publisher();    // created on first use
  eprosima::fastdds::dds::Subscriber& subscriber();  // created on first use

 private:
  ParticipantOptions options_;
  eprosima::fastdds::dds::DomainParticipant* participant_ = nullptr;
  std::array<eprosima::fastdds::dds::Topic*, kTopics.size()> topics_{};
  eprosima::fastdds::dds::Publisher* publisher_ = nullptr;
  eprosima::fastdds::dds::Subscriber* subscriber_ = nullptr;
};

// Loads QoS profiles once per process: `qos_file`, or the embedded ones when it is empty.
// Throws DdsError naming the file when Fast DDS rejects it.
void load_qos_profiles(const std::string& qos_file);

}  // namespace omnisweep::dds
