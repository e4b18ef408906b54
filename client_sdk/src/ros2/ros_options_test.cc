// ROS names and frame ids: what rcl accepts, what the stream's prefix suggests, and errors that
// name the field and value.
#include "omnisweep/ros2/ros_options.h"

#include <gtest/gtest.h>

#include <stdexcept>

namespace omnisweep::ros2 {
namespace {

std::string error_of(const std::string& ros_namespace) {
  try {
    check_namespace(ros_namespace);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(RosOptions, NamespacesFollowRosRules) {
  for (const char* good : {"/", "/omnisweep", "/lab/rig_2", "/_3d", "/a/b/c"})
    EXPECT_EQ(error_of(good), "") << good;
  EXPECT_NE(error_of("omnisweep").find("starting with '/'"), std::string::npos);
  EXPECT_NE(error_of("").find("starting with '/'"), std::string::npos);
  EXPECT_NE(error_of("/rig/").find("must not end with '/'"), std::string::npos);
  EXPECT_NE(error_of("/a//b").find("\"//\""), std::string::npos);
  EXPECT_NE(error_of("/2rig").find("start with a digit (\"2rig\")"), std::string::npos);
  EXPECT_NE(error_of("/rig-1").find("character '-'"), std::string::npos);
  EXPECT_NE(error_of("/a b").find("character ' '"), std::string::npos);
  EXPECT_NE(error_of("/" + std::string(250, 'a')).find("200"), std::string::npos);
  EXPECT_EQ(error_of("/rig-1").rfind("RosOptions.ros_namespace = \"/rig-1\": ", 0), 0u);
}

TEST(RosOptions, CheckNamesFieldAndValue) {
  RosOptions options;
  EXPECT_NO_THROW(options.check());
  options.frame_prefix = "my rig";
  EXPECT_THROW(
      {
        try {
          options.check();
        } catch (const std::invalid_argument& e) {
          EXPECT_STREQ(e.what(),
                       "RosOptions.frame_prefix = \"my rig\": character ' ' is not allowed "
                       "(letters, digits, '_')");
          throw;
        }
      },
      std::invalid_argument);
  options.frame_prefix = "rig";
  options.points_width = 500;
  EXPECT_THROW(options.check(), std::invalid_argument);
  options.points_height = 250;
  EXPECT_NO_THROW(options.check());
  EXPECT_EQ(options.rig_frame(), "rig_rig");
  EXPECT_EQ(options.panorama_frame(), "rig_panorama");
  EXPECT_EQ(options.camera_frame(3), "rig_camera3");
}

TEST(RosOptions, NamesFromTheStreamPrefix) {
  EXPECT_EQ(namespace_for_prefix("omnisweep"), "/omnisweep");
  EXPECT_EQ(namespace_for_prefix("rig-2/front"), "/rig_2/front");
  EXPECT_EQ(namespace_for_prefix("test123/4k"), "/test123/_4k");
  for (const char* prefix : {"omnisweep", "rig-2/front", "test123/4k", "a-b-c/d_e/9"})
    EXPECT_EQ(error_of(namespace_for_prefix(prefix)), "") << prefix;
  EXPECT_EQ(frame_prefix_for_namespace("/lab/rig"), "lab_rig");
  EXPECT_EQ(frame_prefix_for_namespace("/"), "omnisweep");
}

}  // namespace
}  // namespace omnisweep::ros2
