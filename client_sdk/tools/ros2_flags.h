// The ROS 2 flags omnisweep-server, omnisweep-record and omnisweep-play share (docs/ros2.md):
// --no-ros2, --ros-namespace, --ros-frame-prefix, --ros-points.
#pragma once

#include <CLI/CLI.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "omnisweep/ros2/ros_options.h"

namespace omnisweep::tools {

struct Ros2Flags {
  bool off = false;
  ros2::RosOptions options;
  std::vector<int> points = {options.points_width, options.points_height};
};

// `what`: what the flags turn on ("Do not publish the ROS 2 topics", ...).
inline void add_ros2_flags(CLI::App& app, Ros2Flags& flags, const std::string& off_help) {
  app.add_flag("--no-ros2", flags.off, off_help);
  app.add_option("--ros-namespace", flags.options.ros_namespace,
                 "ROS 2 namespace of the image and point topics (default: / + the topic prefix, "
                 "'-' made '_')");
  app.add_option("--ros-frame-prefix", flags.options.frame_prefix,
                 "ROS frame ids <P>_rig, <P>_panorama, <P>_camera<i> (default: the namespace's "
                 "names joined by '_')");
  app.add_option("--ros-points", flags.points,
                 "Size of the ROS point cloud's equirectangular grid, W H (W = 2 H)")
      ->expected(2)
      ->check(CLI::Range(1, 8192));
}

// The ROS options the parsed flags give for a stream with `topic_prefix` (nullopt with
// --no-ros2). Throws std::invalid_argument naming a bad value, or --ros-* given with --no-ros2.
inline std::optional<ros2::RosOptions> ros2_options(const CLI::App& app, Ros2Flags flags,
                                                    const std::string& topic_prefix) {
  if (flags.off) {
    if (app.count("--ros-namespace") || app.count("--ros-frame-prefix") ||
        app.count("--ros-points"))
      throw std::invalid_argument("--no-ros2 turns the ROS 2 topics off; drop the --ros-* options");
    return std::nullopt;
  }
  if (app.count("--ros-namespace") == 0)
    flags.options.ros_namespace = ros2::namespace_for_prefix(topic_prefix);
  if (app.count("--ros-frame-prefix") == 0)
    flags.options.frame_prefix = ros2::frame_prefix_for_namespace(flags.options.ros_namespace);
  flags.options.points_width = flags.points[0];
  flags.options.points_height = flags.points[1];
  flags.options.check();
  return flags.options;
}

}  // namespace omnisweep::tools
