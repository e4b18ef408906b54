#include "omnisweep/ros2/ros_schema.h"

#include <set>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "ros2_message_definitions.h"

namespace omnisweep::ros2 {
namespace {

std::string_view find_definition(std::string_view type) {
  for (const auto& [name, text] : kMessageDefinitions)
    if (name == type) return text;
  throw std::invalid_argument("no ROS 2 message definition for " + std::string(type));
}

bool is_builtin(std::string_view t) {
  static const std::set<std::string_view> builtins = {
      "bool",   "byte",  "char",   "float32", "float64", "int8",   "uint8",  "int16",
      "uint16", "int32", "uint32", "int64",   "uint64",  "string", "wstring"};
  return builtins.count(t) > 0;
}

// The resource names of the non-builtin field types of `type`'s .msg, in order: "Vector3" in
// geometry_msgs is geometry_msgs/msg/Vector3, "std_msgs/Header" is std_msgs/msg/Header.
std::vector<std::string> field_types(std::string_view type) {
  const std::string package(type.substr(0, type.find('/')));
  std::vector<std::string> out;
  std::istringstream lines{std::string(find_definition(type))};
  for (std::string line; std::getline(lines, line);) {
    std::istringstream words(line);
    std::string t, name;
    if (!(words >> t >> name) || t[0] == '#' || line.find('=') != std::string::npos) continue;
    if (const auto bracket = t.find('['); bracket != std::string::npos) t.resize(bracket);
    if (is_builtin(t)) continue;
    const auto slash = t.find('/');
    out.push_back(slash == std::string::npos ? package + "/msg/" + t
                                             : t.substr(0, slash) + "/msg/" + t.substr(slash + 1));
  }
  return out;
}

// The .msg text with every package-qualified field type written in full ("std_msgs/Header" ->
// "std_msgs/msg/Header"), the form of the "MSG:" lines: parsers (Foxglove's @foxglove/rosmsg)
// match a qualified type to its definition by the exact name.
std::string qualified(std::string_view type) {
  std::string out;
  std::istringstream lines{std::string(find_definition(type))};
  for (std::string line; std::getline(lines, line);) {
    const auto end = line.find_first_of(" \t");
    const auto slash = line.find('/');
    if (slash != std::string::npos && slash < end && line.find('/', slash + 1) > end)
      line.insert(slash, "/msg");
    out += line + "\n";
  }
  return out;
}

void add_dependencies(std::string_view type, std::vector<std::string>& order,
                      std::set<std::string>& seen) {
  for (const std::string& t : field_types(type)) {
    if (!seen.insert(t).second) continue;
    order.push_back(t);
    add_dependencies(t, order, seen);
  }
}

}  // namespace

std::string ros_topic(const std::string& ros_namespace, dds::TopicKind kind) {
  return dds::ros_topic_name(ros_namespace, kind).substr(2);  // "rt/a/b" -> "/a/b"
}

std::string ros_type(dds::TopicKind kind) {
  // "sensor_msgs::msg::dds_::CompressedImage_" -> "sensor_msgs/msg/CompressedImage"
  std::string dds(dds::topic_spec(kind).type_name);
  if (dds::is_stream_topic(kind) || dds.size() < 2 || dds.back() != '_')
    throw std::invalid_argument("not a ROS 2 topic: " + dds);
  dds.pop_back();
  const auto package = dds.substr(0, dds.find("::"));
  const auto name = dds.substr(dds.rfind("::") + 2);
  return package + "/msg/" + name;
}

std::string message_definition(std::string_view type) {
  std::string out = qualified(type);
  std::vector<std::string> order;
  std::set<std::string> seen;
  add_dependencies(type, order, seen);
  for (const std::string& t : order) {
    if (!out.empty() && out.back() != '\n') out += '\n';
    out += std::string(80, '=') + "\nMSG: " + t + "\n" + qualified(t);
  }
  return out;
}

std::string offered_qos_profiles(dds::TopicKind kind) {
  // history 1 = keep last; reliability 1 = reliable; durability 1 = transient local,
  // 2 = volatile; liveliness 1 = automatic; durations unset (the largest values).
  const bool latched = kind == dds::TopicKind::kRosTfStatic;
  std::string yaml = "- history: 1\n  depth: " + std::string(latched ? "1" : "2") +
                     "\n  reliability: 1\n  durability: " + (latched ? "1" : "2") + "\n";
  for (const char* duration : {"deadline", "lifespan"})
    yaml += std::string("  ") + duration + ":\n    sec: 2147483647\n    nsec: 4294967295\n";
  yaml +=
      "  liveliness: 1\n  liveliness_lease_duration:\n    sec: 2147483647\n    nsec: "
      "4294967295\n  avoid_ros_namespace_conventions: false";
  return yaml;
}

std::optional<dds::TopicKind> ros_topic_kind(const std::string& ros_namespace,
                                             std::string_view topic) {
  for (const dds::TopicSpec& spec : dds::kTopics)
    if (!dds::is_stream_topic(spec.kind) && ros_topic(ros_namespace, spec.kind) == topic)
      return spec.kind;
  return std::nullopt;
}

}  // namespace omnisweep::ros2
