// How the ROS 2 topics are described outside DDS (rosbag2's MCAP conventions, Foxglove's
// WebSocket advertisements): ROS topic names, ROS type names, the complete .msg definitions
// ("ros2msg": the type's .msg text, then each type it uses after a line of 80 '=' and
// "MSG: <package>/msg/<Type>"; package-qualified field types are written <package>/msg/<Type>
// too, since parsers match them to definitions by exact name), and the offered QoS as rosbag2
// writes it.
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "omnisweep/dds/participant.h"

namespace omnisweep::ros2 {

// "/<namespace>/color/image_raw/compressed", "/tf_static", ...
std::string ros_topic(const std::string& ros_namespace, dds::TopicKind kind);
// "sensor_msgs/msg/CompressedImage", ...
std::string ros_type(dds::TopicKind kind);
// The complete definition of a type by its resource name ("sensor_msgs/msg/PointCloud2");
// throws std::invalid_argument for a type omnisweep does not write.
std::string message_definition(std::string_view type);
// rosbag2's offered_qos_profiles for the topic's writer (a YAML list of one profile, in the
// numeric form rosbag2 has written and read since Foxy).
std::string offered_qos_profiles(dds::TopicKind kind);
// The ROS topic kind of a recorded or advertised ROS topic name under `ros_namespace`.
std::optional<dds::TopicKind> ros_topic_kind(const std::string& ros_namespace,
                                             std::string_view topic);

}  // namespace omnisweep::ros2
