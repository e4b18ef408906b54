// A DDS domain participant with omnisweep's types registered and its QoS profiles loaded: what
// the server's publisher and the SDK's subscriber stand on. One RAII owner per participant, as
// in Fast DDS's examples: the constructor builds participant -> types -> topics and throws
// DdsError naming the entity that failed; the destructor deletes the contained entities, then
// the participant.
//
// Topics (docs/wire-format.md): <prefix>/description, <prefix>/rgbd, <prefix>/status.
// QoS comes from Fast DDS XML profiles (deploy/qos/omnisweep_qos.xml, embedded at build time;
// ParticipantOptions::qos_file loads another file instead).
#pragma once

#include <memory>
#include <stdexcept>
#include <string>

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

enum class TopicKind { kDescription, kFrames, kStatus };

// "<prefix>/description", "<prefix>/rgbd", "<prefix>/status".
std::string topic_name(const std::string& prefix, TopicKind kind);

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
  eprosima::fastdds::dds::Topic* topics_[3] = {nullptr, nullptr, nullptr};
  eprosima::fastdds::dds::Publisher* publisher_ = nullptr;
  eprosima::fastdds::dds::Subscriber* subscriber_ = nullptr;
};

// Loads QoS profiles once per process: `qos_file`, or the embedded ones when it is empty.
// Throws DdsError naming the file when Fast DDS rejects it.
void load_qos_profiles(const std::string& qos_file);

}  // namespace omnisweep::dds
