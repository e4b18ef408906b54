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
}  // namespace eprosima::fastdds::dds

namespace omnisweep::dds {

class DdsError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

enum class TopicKind { kDescription, kFrames, kStatus, kConfidence };

// A topic of the stream: its name after the prefix, its message type (idl/omnisweep_msgs.idl)
// and the QoS profiles of its writer and reader (deploy/qos/omnisweep_qos.xml); an empty
// profile means the frame topic's, which the endpoints choose (live or reliable).
struct TopicSpec {
  TopicKind kind;
  std::string_view suffix;
  std::string_view type_name;
  std::string_view writer_profile;
  std::string_view reader_profile;
};
inline constexpr std::array<TopicSpec, 4> kTopics = {{
    {TopicKind::kDescription, "/description", "omnisweep::msg::StreamDescription",
     "omnisweep_description", "omnisweep_description"},
    {TopicKind::kFrames, "/rgbd", "omnisweep::msg::RgbdFrame", "", ""},
    {TopicKind::kStatus, "/status", "omnisweep::msg::ServerStatus", "omnisweep_status",
     "omnisweep_status"},
    {TopicKind::kConfidence, "/confidence", "omnisweep::msg::ConfidenceFrame", "", ""},
}};
constexpr const TopicSpec& topic_spec(TopicKind kind) { return kTopics[std::size_t(kind)]; }
static_assert(topic_spec(TopicKind::kConfidence).kind == TopicKind::kConfidence,
              "kTopics is in TopicKind's order");

// "<prefix>/description", "<prefix>/rgbd", ...
std::string topic_name(const std::string& prefix, TopicKind kind);
// The kind of a full topic name, by its suffix; nullopt for none of the stream's.
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
  eprosima::fastdds::dds::Topic& topic(TopicKind kind) const;
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
