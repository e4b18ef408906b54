#include "omnisweep/ros2/ros_messages.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <stdexcept>

#include "omnisweep/geometry/equirectangular.h"
#include "omnisweep/wire/wire.h"
#include "ros2_msgsPubSubTypes.h"

namespace omnisweep::ros2 {
namespace {

constexpr std::size_t kDepthHeader = 12;  // int32 format, float A, float B
constexpr std::int32_t kInverseDepth = 0;

template <typename T>
void append(std::vector<std::uint8_t>& out, T value) {
  const auto* p = reinterpret_cast<const std::uint8_t*>(&value);
  out.insert(out.end(), p, p + sizeof(T));  // little endian: every host we build for
}

std::string format_number(double v, int decimals) {
  char text[32];
  std::snprintf(text, sizeof text, "%.*f", decimals, v);
  return text;
}

diagnostic_msgs::msg::KeyValue key_value(std::string key, std::string value) {
  diagnostic_msgs::msg::KeyValue kv;
  kv.key(std::move(key));
  kv.value(std::move(value));
  return kv;
}

}  // namespace

static_assert(std::endian::native == std::endian::little, "ROS messages here are little endian");

std_msgs::msg::Header make_header(std::uint64_t stamp_ns, const std::string& frame_id) {
  std_msgs::msg::Header header;
  header.stamp().sec(std::int32_t(stamp_ns / 1'000'000'000u));
  header.stamp().nanosec(std::uint32_t(stamp_ns % 1'000'000'000u));
  header.frame_id(frame_id);
  return header;
}

std::uint64_t stamp_ns(const builtin_interfaces::msg::Time& stamp) {
  return std::uint64_t(std::max(stamp.sec(), 0)) * 1'000'000'000u + stamp.nanosec();
}

sensor_msgs::msg::CompressedImage compressed_color(const std_msgs::msg::Header& header,
                                                   std::span<const std::uint8_t> jpeg) {
  sensor_msgs::msg::CompressedImage m;
  m.header(header);
  m.format(kJpegFormat);
  m.data().assign(jpeg.begin(), jpeg.end());
  return m;
}

sensor_msgs::msg::CompressedImage compressed_depth(const std_msgs::msg::Header& header,
                                                   ImageView<const std::uint16_t> levels,
                                                   const codec::DistanceParams& params,
                                                   int png_level) {
  params.check();
  if (levels.empty()) throw std::invalid_argument("compressed_depth: expects a non-empty map");
  // Level l is inverse distance lo + (l - 1) step (codec.h), so distance = 1 / (lo + (l - 1)
  // step) = (1 / step) / (l - (1 - lo / step)): A = 1 / step, B = 1 - lo / step.
  const double lo = 1.0 / params.max_distance, hi = 1.0 / params.min_distance;
  const double step = (hi - lo) / double(params.levels - 1);
  const float a = float(1.0 / step), b = float(1.0 - lo / step);
  const cv::Mat view(levels.height(), levels.width(), CV_16UC1,
                     const_cast<std::uint16_t*>(levels.data()));
  std::vector<std::uint8_t> png;
  if (!cv::imencode(".png", view, png, {cv::IMWRITE_PNG_COMPRESSION, png_level}))
    throw std::runtime_error("compressed_depth: OpenCV could not encode the PNG");
  sensor_msgs::msg::CompressedImage m;
  m.header(header);
  m.format(kCompressedDepthFormat);
  std::vector<std::uint8_t>& data = m.data();
  data.reserve(kDepthHeader + png.size());
  append(data, kInverseDepth);
  append(data, a);
  append(data, b);
  data.insert(data.end(), png.begin(), png.end());
  return m;
}

FloatImage decode_compressed_depth(const sensor_msgs::msg::CompressedImage& message) {
  if (message.format().rfind("32FC1; compressedDepth", 0) != 0)
    throw std::invalid_argument("compressedDepth: format \"" + message.format() +
                                "\" is not 32FC1; compressedDepth [png]");
  const std::vector<std::uint8_t>& data = message.data();
  if (data.size() <= kDepthHeader)
    throw std::invalid_argument("compressedDepth: " + std::to_string(data.size()) +
                                " bytes, fewer than its header and an image");
  std::int32_t format;
  float a, b;
  std::memcpy(&format, data.data(), 4);
  std::memcpy(&a, data.data() + 4, 4);
  std::memcpy(&b, data.data() + 8, 4);
  if (format != kInverseDepth)
    throw std::invalid_argument("compressedDepth: format " + std::to_string(format) +
                                " is not inverse depth (0)");
  const cv::Mat png(1, int(data.size() - kDepthHeader), CV_8UC1,
                    const_cast<std::uint8_t*>(data.data() + kDepthHeader));
  const cv::Mat levels = cv::imdecode(png, cv::IMREAD_UNCHANGED);
  if (levels.empty() || levels.type() != CV_16UC1)
    throw std::invalid_argument("compressedDepth: the image is not a 16-bit one-channel PNG");
  FloatImage out(levels.cols, levels.rows);
  for (int y = 0; y < levels.rows; ++y)
    for (int x = 0; x < levels.cols; ++x) {
      const std::uint16_t v = levels.at<std::uint16_t>(y, x);
      out(x, y) = v ? a / (float(v) - b) : std::numeric_limits<float>::quiet_NaN();
    }
  return out;
}

sensor_msgs::msg::Image distance_image(const std_msgs::msg::Header& header, FloatView metres) {
  if (metres.empty()) throw std::invalid_argument("distance_image: expects a non-empty map");
  sensor_msgs::msg::Image m;
  m.header(header);
  m.width(std::uint32_t(metres.width()));
  m.height(std::uint32_t(metres.height()));
  m.encoding("32FC1");
  m.is_bigendian(0);
  m.step(std::uint32_t(metres.width() * 4));
  std::vector<std::uint8_t>& data = m.data();
  data.resize(metres.size() * 4);
  float* out = reinterpret_cast<float*>(data.data());
  const float* in = metres.data();
  for (std::size_t i = 0; i < metres.size(); ++i)
    out[i] = in[i] > 0.0f && std::isfinite(in[i]) ? in[i] : std::numeric_limits<float>::quiet_NaN();
  return m;
}

sensor_msgs::msg::PointCloud2 point_cloud(const std_msgs::msg::Header& header, FloatView metres,
                                          Rgb8View color, const Eigen::Vector3d& viewpoint,
                                          int width, int height) {
  if (metres.empty() || color.width() != metres.width() || color.height() != metres.height())
    throw std::invalid_argument(
        "point_cloud: expects a distance map and a colour image of its size");
  if (width < 1 || height < 1)
    throw std::invalid_argument("point_cloud: the grid must have at least one cell");
  sensor_msgs::msg::PointCloud2 m;
  m.header(header);
  m.width(std::uint32_t(width));
  m.height(std::uint32_t(height));
  const char* names[] = {"x", "y", "z", "rgb"};
  std::vector<sensor_msgs::msg::PointField> fields;
  for (int i = 0; i < 4; ++i) {
    sensor_msgs::msg::PointField f;
    f.name(names[i]);
    f.offset(std::uint32_t(4 * i));
    f.datatype(7);  // FLOAT32
    f.count(1);
    fields.push_back(f);
  }
  m.fields(fields);
  m.is_bigendian(false);
  m.point_step(16);
  m.row_step(16 * std::uint32_t(width));
  m.data().resize(std::size_t(16) * width * height);
  bool dense = true;
  const int w = metres.width(), h = metres.height();
  float* out = reinterpret_cast<float*>(m.data().data());
  for (int j = 0; j < height; ++j) {
    const int y = std::min(h - 1, int((j + 0.5) * h / height));
    for (int i = 0; i < width; ++i, out += 4) {
      const int x = std::min(w - 1, int((i + 0.5) * w / width));
      const float d = metres(x, y);
      const std::uint32_t rgb =
          std::uint32_t(color(x, y, 0)) << 16 | std::uint32_t(color(x, y, 1)) << 8 | color(x, y, 2);
      std::memcpy(out + 3, &rgb, 4);
      if (!(d > 0.0f) || !std::isfinite(d)) {
        out[0] = out[1] = out[2] = std::numeric_limits<float>::quiet_NaN();
        dense = false;
        continue;
      }
      const Eigen::Vector3d p = viewpoint + double(d) * equirect_direction<double>(x, y, w, h);
      out[0] = float(p.x());
      out[1] = float(p.y());
      out[2] = float(p.z());
    }
  }
  m.is_dense(dense);
  return m;
}

tf2_msgs::msg::TFMessage static_transforms(std::uint64_t stamp_ns, const RosOptions& options,
                                           const std::vector<Rigid3d>& rig_from_cam,
                                           const Eigen::Vector3d& viewpoint) {
  const auto transform = [&](const std::string& child, const Rigid3d& pose) {
    geometry_msgs::msg::TransformStamped t;
    t.header(make_header(stamp_ns, options.rig_frame()));
    t.child_frame_id(child);
    t.transform().translation().x(pose.translation.x());
    t.transform().translation().y(pose.translation.y());
    t.transform().translation().z(pose.translation.z());
    const Eigen::Quaterniond q = pose.rotation.normalized();
    t.transform().rotation().x(q.x());
    t.transform().rotation().y(q.y());
    t.transform().rotation().z(q.z());
    t.transform().rotation().w(q.w());
    return t;
  };
  tf2_msgs::msg::TFMessage m;
  m.transforms().push_back(
      transform(options.panorama_frame(), Rigid3d(Eigen::Quaterniond::Identity(), viewpoint)));
  for (std::size_t i = 0; i < rig_from_cam.size(); ++i)
    m.transforms().push_back(transform(options.camera_frame(int(i)), rig_from_cam[i]));
  return m;
}

diagnostic_msgs::msg::DiagnosticArray diagnostics(std::uint64_t stamp_ns, const std::string& name,
                                                  const std::string& hardware_id,
                                                  const msg::ServerStatus& status) {
  constexpr std::uint8_t kOk = 0, kWarn = 1, kError = 2;
  diagnostic_msgs::msg::DiagnosticArray array;
  array.header(make_header(stamp_ns, ""));
  diagnostic_msgs::msg::DiagnosticStatus server;
  server.name(name);
  server.hardware_id(hardware_id);
  std::uint64_t drops = 0;
  for (const auto& d : status.dropped()) drops += d.count();
  const std::string& state = status.state();
  const auto known = wire::parse_server_state(state);
  using wire::ServerState;
  server.level(known == ServerState::kFailed ? kError
               : known == ServerState::kRunning || known == ServerState::kStarting ||
                       known == ServerState::kStopping
                   ? kOk
                   : kWarn);
  server.message(state);
  auto& values = server.values();
  values.push_back(key_value("state", state));
  values.push_back(key_value("fps", format_number(status.fps_out(), 1)));
  values.push_back(key_value("fps_in", format_number(status.fps_in(), 1)));
  for (const auto& stage : status.stage_ms())
    values.push_back(key_value(stage.stage() + "_ms", format_number(stage.ms(), 1)));
  values.push_back(key_value("dropped", std::to_string(drops)));
  for (const auto& d : status.dropped())
    values.push_back(key_value("dropped: " + d.reason(), std::to_string(d.count())));
  values.push_back(key_value("subscribers", std::to_string(status.matched_subscribers())));
  values.push_back(key_value("color_quality", std::to_string(status.color_quality())));
  values.push_back(key_value("frames_over_budget", std::to_string(status.frames_over_budget())));
  array.status().push_back(server);
  for (const auto& camera : status.cameras()) {
    diagnostic_msgs::msg::DiagnosticStatus c;
    c.name(name + ": camera " + std::to_string(camera.camera()));
    c.hardware_id(hardware_id);
    c.level(camera.delivering() ? kOk : kError);
    c.message(camera.delivering() ? "delivering" : "not delivering: " + camera.message());
    c.values().push_back(key_value("fps", format_number(camera.fps(), 1)));
    c.values().push_back(key_value("last_frame_ns", std::to_string(camera.last_frame_ns())));
    array.status().push_back(c);
  }
  return array;
}

FrameInputs frame_inputs(const msg::RgbdFrame& frame) {
  FrameInputs in;
  const auto& times = frame.capture_time_ns();
  in.stamp_ns =
      times.empty() ? frame.processing_start_ns() : *std::min_element(times.begin(), times.end());
  in.width = int(frame.width());
  in.height = int(frame.height());
  in.jpeg = wire::checked_bytes(frame.color(), "colour");
  in.distance = wire::checked_bytes(frame.distance(), "distance");
  in.distance_codec = frame.distance().codec();
  in.distance_params = wire::from_message(frame.distance_params());
  in.viewpoint = {frame.viewpoint().x(), frame.viewpoint().y(), frame.viewpoint().z()};
  return in;
}

std::vector<Rigid3d> rig_from_cameras(const msg::StreamDescription& description) {
  std::vector<Rigid3d> poses;
  for (const RigCamera& camera : wire::rig_from_description(description).cameras)
    poses.push_back(camera.rig_from_cam);
  return poses;
}

FrameConverter::FrameConverter(const RosOptions& options)
    : options_(options),
      distance_codec_(codec::make_distance_codec(codec::kQinv16Zstd)),
      color_codec_(codec::make_color_codec(codec::kJpeg)) {
  options_.check();
}

FrameMessages FrameConverter::convert(const FrameInputs& frame, const WantedTopics& wanted) {
  FrameMessages out;
  const std_msgs::msg::Header image_header = make_header(frame.stamp_ns, options_.panorama_frame());
  if (wanted.color) out.color = compressed_color(image_header, frame.jpeg);
  if (!wanted.compressed_depth && !wanted.distance && !wanted.points) return out;
  if (frame.distance_codec != distance_codec_->name())
    distance_codec_ = codec::make_distance_codec(frame.distance_codec);
  // The stream's own levels: compressedDepth carries them losslessly, and the metres of the
  // image and the points are what every subscriber of the stream decodes.
  const Image<std::uint16_t> levels = distance_codec_->decode_levels(
      frame.distance, frame.width, frame.height, frame.distance_params);
  if (wanted.compressed_depth)
    out.compressed_depth = compressed_depth(image_header, levels, frame.distance_params);
  if (!wanted.distance && !wanted.points) return out;
  const FloatImage metres =
      codec::distance_from_levels(levels, frame.width, frame.height, frame.distance_params);
  if (wanted.distance) out.distance = distance_image(image_header, metres);
  if (wanted.points) {
    Rgb8Image decoded;
    const Rgb8Image* rgb = frame.color;
    if (!rgb) {
      decoded = color_codec_->decode(frame.jpeg, frame.width, frame.height);
      rgb = &decoded;
    }
    out.points = point_cloud(make_header(frame.stamp_ns, options_.rig_frame()), metres, *rgb,
                             frame.viewpoint, options_.points_width, options_.points_height);
  }
  return out;
}

namespace {

// The ROS 2 types this module serialises, each once.
#define OMNISWEEP_ROS2_TYPES(X)        \
  X(sensor_msgs::msg::CompressedImage) \
  X(sensor_msgs::msg::Image)           \
  X(sensor_msgs::msg::PointCloud2)     \
  X(tf2_msgs::msg::TFMessage)          \
  X(diagnostic_msgs::msg::DiagnosticArray)

template <typename Message>
struct PubSub;
#define OMNISWEEP_ROS2_PUBSUB(Type) \
  template <>                       \
  struct PubSub<Type> {             \
    using type = Type##PubSubType;  \
  };
OMNISWEEP_ROS2_TYPES(OMNISWEEP_ROS2_PUBSUB)
#undef OMNISWEEP_ROS2_PUBSUB

}  // namespace

template <typename Message>
std::vector<std::uint8_t> to_cdr(const Message& message) {
  typename PubSub<Message>::type type;
  // The serializer takes a non-const pointer but does not modify the sample.
  auto* sample = const_cast<Message*>(&message);
  eprosima::fastrtps::rtps::SerializedPayload_t payload(type.getSerializedSizeProvider(sample)());
  if (!type.serialize(sample, &payload))
    throw std::runtime_error(std::string("cannot serialise a ") + type.getName());
  return {payload.data, payload.data + payload.length};
}

template <typename Message>
Message from_cdr(std::span<const std::uint8_t> cdr) {
  typename PubSub<Message>::type type;
  if (cdr.size() < 4 || cdr.size() > std::uint64_t(1) << 31)
    throw std::invalid_argument(std::string(type.getName()) + ": " + std::to_string(cdr.size()) +
                                " bytes cannot be a sample");
  eprosima::fastrtps::rtps::SerializedPayload_t payload(std::uint32_t(cdr.size()));
  std::memcpy(payload.data, cdr.data(), cdr.size());
  payload.length = std::uint32_t(cdr.size());
  Message out;
  if (!type.deserialize(&payload, &out))
    throw std::invalid_argument(std::string(type.getName()) + ": the bytes do not parse as CDR");
  return out;
}

#define OMNISWEEP_ROS2_CDR(Type)                                \
  template std::vector<std::uint8_t> to_cdr<Type>(const Type&); \
  template Type from_cdr<Type>(std::span<const std::uint8_t>);
OMNISWEEP_ROS2_TYPES(OMNISWEEP_ROS2_CDR)
#undef OMNISWEEP_ROS2_CDR
#undef OMNISWEEP_ROS2_TYPES

}  // namespace omnisweep::ros2
