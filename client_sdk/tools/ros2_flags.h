// The ROS 2 flags omnisweep-server, omnisweep-record and omnisweep-play share (docs/ros2.md):
// --no-ros2, --ros-namespace, --ros-frame-prefix, --ros-points; and the Foxglove WebSocket
// server's of omnisweep-server and omnisweep-play: --foxglove-port, --foxglove-address.
#pragma once

#include <CLI/CLI.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "omnisweep/foxglove/foxglove_server.h"
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

struct FoxgloveFlags {
  foxglove::FoxgloveOptions options;
};

inline void add_foxglove_flags(CLI::App& app, FoxgloveFlags& flags) {
  app.add_option("--foxglove-port", flags.options.port,
                 "Serve the ROS 2 topics to Foxglove over WebSocket on this port (8765 is "
                 "Foxglove's default; 0: any free port; off unless given)")
      ->check(CLI::Range(0, 65535));
  app.add_option("--foxglove-address", flags.options.address,
                 "Address the Foxglove server listens on (default 0.0.0.0: every interface)");
  app.add_option("--foxglove-client-queue", flags.options.client_queue_bytes,
                 "Bytes a Foxglove client may leave unsent before it loses messages (default "
                 "16 MiB)")
      ->check(CLI::Range(std::size_t(1024), std::size_t(1) << 34));
}

// The Foxglove server's options when --foxglove-port was given (nullopt otherwise). Throws
// std::invalid_argument when it is given with --no-ros2 (it serves the ROS 2 topics).
inline std::optional<foxglove::FoxgloveOptions> foxglove_options(const CLI::App& app,
                                                                 const FoxgloveFlags& flags,
                                                                 bool ros2_on) {
  if (app.count("--foxglove-port") == 0) {
    if (app.count("--foxglove-address") || app.count("--foxglove-client-queue"))
      throw std::invalid_argument(
          "--foxglove-address and --foxglove-client-queue need --foxglove-port");
    return std::nullopt;
  }
  if (!ros2_on)
    throw std::invalid_argument(
        "--foxglove-port serves the ROS 2 topics; it cannot be used with --no-ros2");
  flags.options.check();
  return flags.options;
}

}  // namespace omnisweep::tools
