// The stream's frames as ROS 2 messages (docs/ros2.md): the JPEG as it travels, the distance
// as compressedDepth (lossless from the stream's 16-bit levels) and as a 32FC1 image, a point
// cloud, the rig's static transforms and the server's diagnostics. Types are the generated
// ROS 2 types of idl/ros2/ros2_msgs.idl. Distances are radial, along each panorama pixel's ray
// from the viewpoint, not along a z axis as REP 118 depth images are.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "omnisweep/codec/codec.h"
#include "omnisweep/geometry/rigid3.h"
#include "omnisweep/image/image.h"
#include "omnisweep/ros2/ros_options.h"
#include "omnisweep_msgs.h"
#include "ros2_msgs.h"

namespace omnisweep::ros2 {

// compressed_image_transport's format string for a JPEG of an RGB image, and
// compressed_depth_image_transport's for a 32FC1 image sent as a 16-bit inverse-depth PNG.
inline constexpr const char* kJpegFormat = "rgb8; jpeg compressed bgr8";
inline constexpr const char* kCompressedDepthFormat = "32FC1; compressedDepth png";

std_msgs::msg::Header make_header(std::uint64_t stamp_ns, const std::string& frame_id);
std::uint64_t stamp_ns(const builtin_interfaces::msg::Time& stamp);

// sensor_msgs/CompressedImage carrying these JPEG bytes unchanged (no second encode).
sensor_msgs::msg::CompressedImage compressed_color(const std_msgs::msg::Header& header,
                                                   std::span<const std::uint8_t> jpeg);

// compressedDepth: a 12-byte header (int32 0 = inverse depth, float A, float B), then `levels`
// as a 16-bit PNG, so that a receiver's distance A / (v - B) is the stream's own
// (DistanceCodec::decode_levels; level 0, no value, decodes to NaN). A = 1 / step and
// B = 1 - (1 / d_max) / step, step being the inverse distance of one level.
sensor_msgs::msg::CompressedImage compressed_depth(const std_msgs::msg::Header& header,
                                                   ImageView<const std::uint16_t> levels,
                                                   const codec::DistanceParams& params,
                                                   int png_level = 1);
// Its inverse, as compressed_depth_image_transport decodes it: metres, NaN for no value.
// Throws std::invalid_argument for a message that is not an inverse-depth PNG compressedDepth.
FloatImage decode_compressed_depth(const sensor_msgs::msg::CompressedImage& message);

// sensor_msgs/Image "32FC1", little endian, metres; 0 (no value) becomes NaN (REP 117).
sensor_msgs::msg::Image distance_image(const std_msgs::msg::Header& header, FloatView metres);

// sensor_msgs/PointCloud2 in the rig frame: fields x, y, z, rgb (float32 each, rgb packed as
// 0x00RRGGBB as PCL and RViz read it), organised as the width x height equirectangular grid;
// each point is the panorama pixel nearest the grid cell's centre (no averaging across edges),
// viewpoint + distance x that pixel's ray. Pixels with no value give NaN points (is_dense
// false).
sensor_msgs::msg::PointCloud2 point_cloud(const std_msgs::msg::Header& header, FloatView metres,
                                          Rgb8View color, const Eigen::Vector3d& viewpoint,
                                          int width, int height);

// tf2_msgs/TFMessage for /tf_static: rig -> panorama (the viewpoint, the rig's axes) and
// rig -> camera<i> (rig_from_cam of each camera).
tf2_msgs::msg::TFMessage static_transforms(std::uint64_t stamp_ns, const RosOptions& options,
                                           const std::vector<Rigid3d>& rig_from_cam,
                                           const Eigen::Vector3d& viewpoint);

// diagnostic_msgs/DiagnosticArray: one status `name` for the server (state, fps, per-stage ms,
// drops, subscribers, colour quality; WARN when stalled or dropping, ERROR when failed) and one
// per camera (<name>: camera <i>; ERROR when not delivering).
diagnostic_msgs::msg::DiagnosticArray diagnostics(std::uint64_t stamp_ns, const std::string& name,
                                                  const std::string& hardware_id,
                                                  const msg::ServerStatus& status);

// One frame of the stream, as the converter needs it (views: nothing is copied until a message
// is made).
struct FrameInputs {
  std::uint64_t stamp_ns = 0;              // header.stamp: the capture time (the earliest camera's)
  int width = 0, height = 0;               // panorama
  std::span<const std::uint8_t> jpeg;      // the colour payload ("jpeg")
  std::span<const std::uint8_t> distance;  // the distance payload
  std::string distance_codec{codec::kQinv16Zstd};
  codec::DistanceParams distance_params;
  // The colour the point cloud takes; null: the JPEG is decoded when the points are wanted.
  const Rgb8Image* color = nullptr;
  Eigen::Vector3d viewpoint = Eigen::Vector3d::Zero();  // rig frame
};
// The inputs of a frame of the stream as received (its payloads' CRCs and parameters checked;
// throws wire::WireError naming the field at fault). Views into `frame`.
FrameInputs frame_inputs(const msg::RgbdFrame& frame);
// The rig's camera poses of a stream description (for static_transforms).
std::vector<Rigid3d> rig_from_cameras(const msg::StreamDescription& description);

// Which frame topics to make.
struct WantedTopics {
  bool color = false, compressed_depth = false, distance = false, points = false;
  bool any() const { return color || compressed_depth || distance || points; }
  WantedTopics operator|(const WantedTopics& o) const {
    return {color || o.color, compressed_depth || o.compressed_depth, distance || o.distance,
            points || o.points};
  }
};

struct FrameMessages {
  std::optional<sensor_msgs::msg::CompressedImage> color, compressed_depth;
  std::optional<sensor_msgs::msg::Image> distance;
  std::optional<sensor_msgs::msg::PointCloud2> points;
};

// Makes a frame's ROS messages, only those wanted: the distance payload is decoded once (to its
// levels, then metres) and only when a distance topic is wanted.
class FrameConverter {
 public:
  explicit FrameConverter(const RosOptions& options);
  // Throws codec::CodecError for a payload that does not decode.
  FrameMessages convert(const FrameInputs& frame, const WantedTopics& wanted);

 private:
  RosOptions options_;
  std::unique_ptr<codec::DistanceCodec> distance_codec_;
  std::unique_ptr<codec::ColorCodec> color_codec_;
};

// A message's CDR serialisation with its encapsulation header, as DDS sends it and rosbag2 and
// Foxglove store it; and back (throws std::invalid_argument when `cdr` does not parse).
template <typename Message>
std::vector<std::uint8_t> to_cdr(const Message& message);
template <typename Message>
Message from_cdr(std::span<const std::uint8_t> cdr);

}  // namespace omnisweep::ros2
