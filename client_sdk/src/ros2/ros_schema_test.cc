// ROS topic and type names, and complete .msg definitions in rosbag2's "ros2msg" form.
#include "omnisweep/ros2/ros_schema.h"

#include <gtest/gtest.h>

namespace omnisweep::ros2 {
namespace {

using dds::TopicKind;

TEST(RosSchema, TopicAndTypeNames) {
  EXPECT_EQ(ros_topic("/lab/rig", TopicKind::kRosColor), "/lab/rig/color/image_raw/compressed");
  EXPECT_EQ(ros_topic("/lab/rig", TopicKind::kRosTfStatic), "/tf_static");
  EXPECT_EQ(ros_topic("/", TopicKind::kRosPoints), "/points");
  EXPECT_EQ(ros_type(TopicKind::kRosCompressedDepth), "sensor_msgs/msg/CompressedImage");
  EXPECT_EQ(ros_type(TopicKind::kRosDiagnostics), "diagnostic_msgs/msg/DiagnosticArray");
  EXPECT_THROW(ros_type(TopicKind::kFrames), std::invalid_argument);
  EXPECT_EQ(ros_topic_kind("/lab", "/lab/distance/image_raw"), TopicKind::kRosDistance);
  EXPECT_EQ(ros_topic_kind("/lab", "/other/distance/image_raw"), std::nullopt);
}

TEST(RosSchema, DefinitionsCarryEveryTypeTheyUseOnce) {
  const std::string tf = message_definition("tf2_msgs/msg/TFMessage");
  const std::string separator = std::string(80, '=') + "\n";
  EXPECT_EQ(tf.rfind("geometry_msgs/msg/TransformStamped[] transforms\n", 0), 0u) << tf;
  for (const char* type : {"geometry_msgs/msg/TransformStamped", "std_msgs/msg/Header",
                           "builtin_interfaces/msg/Time", "geometry_msgs/msg/Transform",
                           "geometry_msgs/msg/Vector3", "geometry_msgs/msg/Quaternion"}) {
    const std::string block = separator + "MSG: " + type + "\n";
    EXPECT_NE(tf.find(block), std::string::npos) << type << "\n" << tf;
    EXPECT_EQ(tf.find(block), tf.rfind(block)) << type;
  }
  const std::string cloud = message_definition("sensor_msgs/msg/PointCloud2");
  EXPECT_NE(cloud.find("MSG: sensor_msgs/msg/PointField\n"), std::string::npos);
  EXPECT_NE(cloud.find("uint8 FLOAT32 = 7"), std::string::npos);
  EXPECT_EQ(message_definition("std_msgs/msg/Header").find("MSG: builtin_interfaces/msg/Time"),
            std::string("builtin_interfaces/msg/Time stamp\nstring frame_id\n").size() + 81);
  EXPECT_THROW(message_definition("sensor_msgs/msg/Imu"), std::invalid_argument);
  // Every ROS topic's type has its definition.
  for (const dds::TopicSpec& spec : dds::kTopics) {
    if (!dds::is_stream_topic(spec.kind)) {
      EXPECT_NO_THROW(message_definition(ros_type(spec.kind)));
    }
  }
}

TEST(RosSchema, OfferedQosAsRosbag2WritesIt) {
  EXPECT_NE(offered_qos_profiles(TopicKind::kRosTfStatic).find("durability: 1\n"),
            std::string::npos);
  const std::string color = offered_qos_profiles(TopicKind::kRosColor);
  EXPECT_EQ(color.rfind("- history: 1\n  depth: 2\n  reliability: 1\n  durability: 2\n", 0), 0u)
      << color;
}

}  // namespace
}  // namespace omnisweep::ros2
