#include "omnisweep/dds/participant.h"

#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/topic/Topic.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>
#include <filesystem>
#include <mutex>
#include <set>
#include <utility>

#include "omnisweep_msgsPubSubTypes.h"
#include "qos_profiles.h"

namespace omnisweep::dds {
namespace fdds = eprosima::fastdds::dds;
using ReturnCode_t = eprosima::fastrtps::types::ReturnCode_t;

namespace {
// The builtin DDS Security plugins' file properties and the file of a credentials folder
// (deploy/security/make-credentials.sh) each one names.
constexpr std::pair<const char*, const char*> kSecurityFiles[] = {
    {"dds.sec.auth.builtin.PKI-DH.identity_ca", "identity_ca.pem"},
    {"dds.sec.auth.builtin.PKI-DH.identity_certificate", "cert.pem"},
    {"dds.sec.auth.builtin.PKI-DH.private_key", "key.pem"},
    {"dds.sec.access.builtin.Access-Permissions.permissions_ca", "permissions_ca.pem"},
    {"dds.sec.access.builtin.Access-Permissions.governance", "governance.p7s"},
    {"dds.sec.access.builtin.Access-Permissions.permissions", "permissions.p7s"}};
}  // namespace

std::string topic_name(const std::string& prefix, TopicKind kind) {
  return prefix + std::string(topic_spec(kind).suffix);
}

std::string ros_topic_name(const std::string& ros_namespace, TopicKind kind) {
  const TopicSpec& spec = topic_spec(kind);
  if (spec.scope == TopicScope::kStream)
    throw DdsError("ros_topic_name: " + std::string(spec.suffix) + " is a stream topic");
  if (spec.scope == TopicScope::kRosRoot || ros_namespace == "/")
    return "rt" + std::string(spec.suffix);
  return "rt" + ros_namespace + std::string(spec.suffix);
}

std::optional<TopicKind> topic_kind_of(std::string_view name) {
  const bool ros = name.starts_with("rt/");
  for (const TopicSpec& topic : kTopics) {
    if ((topic.scope != TopicScope::kStream) != ros) continue;
    if (topic.scope == TopicScope::kRosRoot
            ? name.substr(2) == topic.suffix
            : name.size() > topic.suffix.size() && name.ends_with(topic.suffix))
      return topic.kind;
  }
  return std::nullopt;
}

namespace {

fdds::TypeSupport type_support(TopicKind kind) {
  switch (kind) {
    case TopicKind::kDescription:
      return fdds::TypeSupport(new msg::StreamDescriptionPubSubType());
    case TopicKind::kFrames:
      return fdds::TypeSupport(new msg::RgbdFramePubSubType());
    case TopicKind::kStatus:
      return fdds::TypeSupport(new msg::ServerStatusPubSubType());
    case TopicKind::kConfidence:
      return fdds::TypeSupport(new msg::ConfidenceFramePubSubType());
    default:
      break;
  }
  throw DdsError("not a stream topic: " + std::string(topic_spec(kind).suffix));
}

}  // namespace

void ParticipantOptions::check() const {
  if (domain < 0 || domain > 232)
    throw DdsError("domain id " + std::to_string(domain) + " is outside 0-232");
  if (topic_prefix.empty() || topic_prefix.size() > 100)
    throw DdsError("topic prefix must have 1-100 characters");
  for (char c : topic_prefix) {
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-' && c != '/') {
      throw DdsError("topic prefix \"" + topic_prefix + "\": character '" + std::string(1, c) +
                     "' is not allowed (letters, digits, '_', '-', '/')");
    }
  }
  if (topic_prefix.front() == '/' || topic_prefix.back() == '/' ||
      topic_prefix.find("//") != std::string::npos) {
    throw DdsError("topic prefix \"" + topic_prefix + "\": '/' only between words");
  }
  if (!qos_file.empty() && !std::filesystem::is_regular_file(qos_file))
    throw DdsError("QoS profile file " + qos_file + " does not exist");
  if (!security_dir.empty()) {
    for (const auto& [property, file] : kSecurityFiles) {
      if (!std::filesystem::is_regular_file(std::filesystem::path(security_dir) / file)) {
        throw DdsError("security folder " + security_dir + " has no " + file +
                       " (make one with deploy/security/make-credentials.sh)");
      }
    }
  }
}

namespace {

// The builtin DDS Security plugins' properties for the credentials in `dir`; paths as
// file:///absolute URIs, the only form the plugins accept.
void add_security_properties(const std::string& dir, fdds::DomainParticipantQos& qos) {
  auto& properties = qos.properties().properties();
  properties.emplace_back("dds.sec.auth.plugin", "builtin.PKI-DH");
  properties.emplace_back("dds.sec.access.plugin", "builtin.Access-Permissions");
  properties.emplace_back("dds.sec.crypto.plugin", "builtin.AES-GCM-GMAC");
  for (const auto& [property, file] : kSecurityFiles) {
    properties.emplace_back(
        property,
        "file://" + std::filesystem::absolute(std::filesystem::path(dir) / file).string());
  }
}

}  // namespace

void load_qos_profiles(const std::string& qos_file) {
  static std::mutex mutex;
  static std::set<std::string> loaded;
  const std::lock_guard lock(mutex);
  const std::string key = qos_file.empty() ? "<embedded>" : qos_file;
  if (loaded.count(key)) return;
  auto* factory = fdds::DomainParticipantFactory::get_instance();
  const ReturnCode_t result = qos_file.empty()
                                  ? factory->load_XML_profiles_string(
                                        kEmbeddedQosProfiles, sizeof(kEmbeddedQosProfiles) - 1)
                                  : factory->load_XML_profiles_file(qos_file);
  if (result != ReturnCode_t::RETCODE_OK) {
    throw DdsError(qos_file.empty() ? "the embedded QoS profiles do not load"
                                    : "QoS profile file " + qos_file +
                                          " is not a valid Fast DDS XML profile file");
  }
  loaded.insert(key);
}

Participant::Participant(const ParticipantOptions& options) : options_(options) {
  options_.check();
  load_qos_profiles(options_.qos_file);
  auto* factory = fdds::DomainParticipantFactory::get_instance();
  fdds::DomainParticipantQos qos;
  if (factory->get_participant_qos_from_profile("omnisweep_participant", qos) !=
      ReturnCode_t::RETCODE_OK) {
    throw DdsError(
        "QoS profile \"omnisweep_participant\" is missing from " +
        (options_.qos_file.empty() ? std::string("the embedded profiles") : options_.qos_file));
  }
  qos.name(options_.name);
  if (!options_.security_dir.empty()) add_security_properties(options_.security_dir, qos);
  participant_ = factory->create_participant(options_.domain, qos);
  if (!participant_) {
    throw DdsError("cannot create the DDS participant on domain " +
                   std::to_string(options_.domain) +
                   (options_.security_dir.empty()
                        ? std::string()
                        : " with the credentials in " + options_.security_dir +
                              " (expired, not signed by their CA, or a subject that does not "
                              "match the permissions)"));
  }
  try {
    for (const TopicSpec& spec : kTopics) {
      if (spec.scope == TopicScope::kStream)
        add_topic(spec.kind, topic_name(options_.topic_prefix, spec.kind), type_support(spec.kind));
    }
  } catch (...) {
    participant_->delete_contained_entities();
    factory->delete_participant(participant_);
    throw;
  }
}

Participant::~Participant() {
  participant_->delete_contained_entities();
  fdds::DomainParticipantFactory::get_instance()->delete_participant(participant_);
}

fdds::Topic& Participant::topic(TopicKind kind) const {
  if (!topics_[int(kind)])
    throw DdsError("topic " + std::string(topic_spec(kind).suffix) + " was not made");
  return *topics_[int(kind)];
}

fdds::Topic& Participant::add_topic(TopicKind kind, const std::string& name,
                                    const fdds::TypeSupport& type) {
  if (topics_[int(kind)]) return *topics_[int(kind)];
  const TopicSpec& spec = topic_spec(kind);
  if (type.get_type_name() != spec.type_name)
    throw DdsError("DDS type " + type.get_type_name() + " is not kTopics' " +
                   std::string(spec.type_name));
  // A type shared by two topics (the ROS images) is registered once.
  if (!participant_->find_type(type.get_type_name()) &&
      type.register_type(participant_) != ReturnCode_t::RETCODE_OK)
    throw DdsError("cannot register DDS type " + type.get_type_name());
  topics_[int(kind)] =
      participant_->create_topic(name, type.get_type_name(), fdds::TOPIC_QOS_DEFAULT);
  if (!topics_[int(kind)]) throw DdsError("cannot create DDS topic " + name);
  return *topics_[int(kind)];
}

fdds::Publisher& Participant::publisher() {
  if (!publisher_) {
    publisher_ = participant_->create_publisher(fdds::PUBLISHER_QOS_DEFAULT);
    if (!publisher_) throw DdsError("cannot create the DDS publisher");
  }
  return *publisher_;
}

fdds::Subscriber& Participant::subscriber() {
  if (!subscriber_) {
    subscriber_ = participant_->create_subscriber(fdds::SUBSCRIBER_QOS_DEFAULT);
    if (!subscriber_) throw DdsError("cannot create the DDS subscriber");
  }
  return *subscriber_;
}

}  // namespace omnisweep::dds
