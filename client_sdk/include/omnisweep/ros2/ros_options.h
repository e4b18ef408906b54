// What the ROS 2 topics are called and which frames they name (docs/ros2.md): the namespace,
// the frame ids, and the point cloud's size. Checked like the other options (COLMAP's Check()).
#pragma once

#include <string>
#include <string_view>

namespace omnisweep::ros2 {

struct RosOptions {
  // The ROS namespace of the image and point topics: /omnisweep gives
  // /omnisweep/color/image_raw/compressed (DDS topic rt/omnisweep/color/image_raw/compressed).
  // /tf_static and /diagnostics are global, as in every ROS system.
  std::string ros_namespace = "/omnisweep";
  // Frame ids: <frame_prefix>_rig (the calibration's rig frame; points and transforms),
  // <frame_prefix>_panorama (the panorama's centre, axes of the rig; the images) and
  // <frame_prefix>_camera<i> (each camera, optical axes as in the calibration).
  std::string frame_prefix = "omnisweep";
  // The point cloud's size: the panorama sampled on this equirectangular grid (RViz draws
  // points, not an equirectangular image).
  int points_width = 512;
  int points_height = 256;

  std::string rig_frame() const { return frame_prefix + "_rig"; }
  std::string panorama_frame() const { return frame_prefix + "_panorama"; }
  std::string camera_frame(int camera) const {
    return frame_prefix + "_camera" + std::to_string(camera);
  }

  // Throws std::invalid_argument naming the field, its value and what is allowed.
  void check() const;
};

// Throws std::invalid_argument unless `name` is a fully qualified ROS 2 namespace: "/", or '/'
// followed by tokens of letters, digits and '_' that do not start with a digit, separated by
// single '/', no trailing '/' (rcl's rules), at most 200 characters.
void check_namespace(const std::string& name);

// The namespace the stream's topic prefix suggests: "/" + prefix, with characters ROS names do
// not allow ('-') made '_' and a token that starts with a digit given a leading '_'
// ("rig-2/front" -> "/rig_2/front").
std::string namespace_for_prefix(std::string_view topic_prefix);

// A frame prefix from a namespace: its tokens joined by '_' ("/lab/rig" -> "lab_rig"; "/" ->
// "omnisweep").
std::string frame_prefix_for_namespace(std::string_view ros_namespace);

}  // namespace omnisweep::ros2
