#include "omnisweep/ros2/ros_options.h"

#include <cctype>
#include <stdexcept>

namespace omnisweep::ros2 {
namespace {

bool is_token_char(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; }

std::invalid_argument bad(std::string_view field, const std::string& value, std::string_view why) {
  return std::invalid_argument("RosOptions." + std::string(field) + " = \"" + value +
                               "\": " + std::string(why));
}

}  // namespace

void check_namespace(const std::string& name) {
  const auto fail = [&](std::string_view why) { return bad("ros_namespace", name, why); };
  if (name.empty() || name.front() != '/')
    throw fail("must be a fully qualified ROS namespace, starting with '/' (e.g. /omnisweep)");
  if (name.size() > 200) throw fail("must have at most 200 characters");
  if (name == "/") return;
  if (name.back() == '/') throw fail("must not end with '/'");
  std::size_t token_start = 1;
  for (std::size_t i = 1; i <= name.size(); ++i) {
    if (i == name.size() || name[i] == '/') {
      if (i == token_start) throw fail("must not contain \"//\"");
      if (std::isdigit(static_cast<unsigned char>(name[token_start])))
        throw fail("a name must not start with a digit (\"" +
                   name.substr(token_start, i - token_start) + "\")");
      token_start = i + 1;
    } else if (!is_token_char(name[i])) {
      throw fail("character '" + std::string(1, name[i]) +
                 "' is not allowed (letters, digits, '_', '/' between names)");
    }
  }
}

void RosOptions::check() const {
  check_namespace(ros_namespace);
  if (frame_prefix.empty() || frame_prefix.size() > 100 ||
      std::isdigit(static_cast<unsigned char>(frame_prefix.front())))
    throw bad("frame_prefix", frame_prefix,
              "must have 1-100 characters and not start with a digit");
  for (char c : frame_prefix)
    if (!is_token_char(c))
      throw bad("frame_prefix", frame_prefix,
                "character '" + std::string(1, c) + "' is not allowed (letters, digits, '_')");
  if (points_width < 2 || points_width > 8192 || points_height < 1 || points_height > 4096 ||
      points_width != 2 * points_height)
    throw std::invalid_argument("RosOptions.points = " + std::to_string(points_width) + "x" +
                                std::to_string(points_height) +
                                ": must be W x W/2 with 2 <= W <= 8192");
}

std::string namespace_for_prefix(std::string_view topic_prefix) {
  std::string out = "/";
  bool token_start = true;
  for (char c : topic_prefix) {
    if (c == '/') {
      if (!token_start) out += '/';
      token_start = true;
      continue;
    }
    if (token_start && std::isdigit(static_cast<unsigned char>(c))) out += '_';
    out += is_token_char(c) ? c : '_';
    token_start = false;
  }
  if (out.size() > 1 && out.back() == '/') out.pop_back();
  return out;
}

std::string frame_prefix_for_namespace(std::string_view ros_namespace) {
  std::string out;
  for (char c : ros_namespace.substr(ros_namespace.empty() ? 0 : 1)) out += c == '/' ? '_' : c;
  return out.empty() ? std::string("omnisweep") : out;
}

}  // namespace omnisweep::ros2
