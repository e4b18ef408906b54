// The stream's frames as ROS 2 messages: compressedDepth decodes (as compressed_depth_image_
// transport does) to the stream's own distances, the 32FC1 image and the point cloud lie on the
// distance map, transforms and diagnostics carry what the server knows, and samples serialise
// as ROS's XCDR1 little-endian CDR.
#include "omnisweep/ros2/ros_messages.h"

#include <fastdds/rtps/common/SerializedPayload.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

#include "omnisweep/geometry/equirectangular.h"
#include "ros2_msgsPubSubTypes.h"
#include "tests/support/status_fixture.h"

namespace omnisweep::ros2 {
namespace {

FloatImage test_distance(int w, int h) {
  FloatImage d(w, h);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) d(x, y) = unit(rng) < 0.05f ? 0.0f : 0.6f + 60.0f * unit(rng);
  return d;
}

Rgb8Image test_color(int w, int h) {
  Rgb8Image im(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      im(x, y, 0) = std::uint8_t(x);
      im(x, y, 1) = std::uint8_t(y);
      im(x, y, 2) = std::uint8_t(x + y);
    }
  return im;
}

TEST(RosMessages, CompressedDepthDecodesToTheStreamsDistances) {
  const auto codec = codec::make_distance_codec(codec::kQinv16Zstd);
  const FloatImage d = test_distance(96, 48);
  for (const codec::DistanceParams params :
       {codec::DistanceParams{}, codec::DistanceParams{.levels = 65535},
        codec::DistanceParams{.levels = 2048, .downsample = 4}}) {
    const codec::Bytes payload = codec->encode(d, params);
    const Image<std::uint16_t> levels = codec->decode_levels(payload, 96, 48, params);
    const auto message = compressed_depth(make_header(123, "p"), levels, params);
    EXPECT_EQ(message.format(), "32FC1; compressedDepth png");
    std::int32_t format = -1;
    std::memcpy(&format, message.data().data(), 4);
    EXPECT_EQ(format, 0);  // inverse depth
    const FloatImage ros = decode_compressed_depth(message);
    ASSERT_EQ(ros.width(), levels.width());
    ASSERT_EQ(ros.height(), levels.height());
    const FloatImage ours = codec->decode(payload, 96, 48, params);
    const int ds = int(params.downsample);
    double worst = 0;
    for (int y = 0; y < ros.height(); ++y)
      for (int x = 0; x < ros.width(); ++x) {
        const float stream = ours(x * ds, y * ds);
        if (stream == 0.0f) {
          ASSERT_TRUE(std::isnan(ros(x, y))) << x << "," << y;
          continue;
        }
        worst = std::max(worst, std::abs(1.0 / ros(x, y) - 1.0 / stream));
      }
    // The same level, read through float A and B: within 5 % of half a level (float rounding).
    EXPECT_LT(worst, params.max_quantisation_error() * 0.05) << params.levels;
  }
}

TEST(RosMessages, CompressedDepthRejectsWhatIsNotOne) {
  sensor_msgs::msg::CompressedImage m;
  m.format("rgb8; jpeg compressed bgr8");
  EXPECT_THROW(decode_compressed_depth(m), std::invalid_argument);
  m.format(kCompressedDepthFormat);
  m.data() = {0, 0, 0, 0};
  EXPECT_THROW(decode_compressed_depth(m), std::invalid_argument);
  m.data().assign(40, 0);
  EXPECT_THROW(decode_compressed_depth(m), std::invalid_argument);  // not a PNG
}

TEST(RosMessages, DistanceImageIsMetresWithNaNHoles) {
  const FloatImage d = test_distance(16, 8);
  const auto m = distance_image(make_header(5'000'000'123ull, "omnisweep_panorama"), d);
  EXPECT_EQ(m.encoding(), "32FC1");
  EXPECT_EQ(m.header().stamp().sec(), 5);
  EXPECT_EQ(m.header().stamp().nanosec(), 123u);
  EXPECT_EQ(stamp_ns(m.header().stamp()), 5'000'000'123ull);
  EXPECT_EQ(m.width(), 16u);
  EXPECT_EQ(m.step(), 64u);
  ASSERT_EQ(m.data().size(), 16u * 8 * 4);
  const float* v = reinterpret_cast<const float*>(m.data().data());
  for (std::size_t i = 0; i < d.size(); ++i) {
    if (d.data()[i] == 0.0f)
      EXPECT_TRUE(std::isnan(v[i]));
    else
      EXPECT_EQ(v[i], d.data()[i]);
  }
}

TEST(RosMessages, PointsLieOnTheDistanceMap) {
  const int w = 64, h = 32;
  const FloatImage d = test_distance(w, h);
  const Rgb8Image c = test_color(w, h);
  const Eigen::Vector3d viewpoint(0.1, -0.2, 0.3);
  const auto m = point_cloud(make_header(1, "omnisweep_rig"), d, c, viewpoint, 16, 8);
  ASSERT_EQ(m.fields().size(), 4u);
  EXPECT_EQ(m.fields()[3].name(), "rgb");
  EXPECT_EQ(m.fields()[3].offset(), 12u);
  EXPECT_EQ(m.point_step(), 16u);
  ASSERT_EQ(m.data().size(), 16u * 16 * 8);
  int holes = 0;
  for (int j = 0; j < 8; ++j)
    for (int i = 0; i < 16; ++i) {
      const float* p =
          reinterpret_cast<const float*>(m.data().data()) + std::ptrdiff_t(4) * (j * 16 + i);
      // The panorama pixel nearest the cell's centre.
      const int x = int((i + 0.5) * w / 16), y = int((j + 0.5) * h / 8);
      std::uint32_t rgb;
      std::memcpy(&rgb, p + 3, 4);
      EXPECT_EQ(rgb, std::uint32_t(c(x, y, 0)) << 16 | std::uint32_t(c(x, y, 1)) << 8 | c(x, y, 2));
      if (d(x, y) == 0.0f) {
        EXPECT_TRUE(std::isnan(p[0]));
        ++holes;
        continue;
      }
      const Eigen::Vector3d ray = Eigen::Vector3d(p[0], p[1], p[2]) - viewpoint;
      EXPECT_NEAR(ray.norm(), d(x, y), 1e-5 * d(x, y));
      const Eigen::Vector2d pixel = equirect_pixel<double>(ray, w, h);
      EXPECT_NEAR(pixel.x(), x, 1e-3);
      EXPECT_NEAR(pixel.y(), y, 1e-3);
    }
  EXPECT_EQ(m.is_dense(), holes == 0);
}

TEST(RosMessages, StaticTransformsNameEveryFrame) {
  RosOptions options;
  options.frame_prefix = "lab";
  const std::vector<Rigid3d> cams = {
      Rigid3d(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0.1, 0, 0)),
      Rigid3d(Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitY())),
              Eigen::Vector3d(0, 0, 0.1))};
  const auto m = static_transforms(7, options, cams, Eigen::Vector3d(0, 0.05, 0));
  ASSERT_EQ(m.transforms().size(), 3u);
  EXPECT_EQ(m.transforms()[0].header().frame_id(), "lab_rig");
  EXPECT_EQ(m.transforms()[0].child_frame_id(), "lab_panorama");
  EXPECT_EQ(m.transforms()[0].transform().translation().y(), 0.05);
  EXPECT_EQ(m.transforms()[2].child_frame_id(), "lab_camera1");
  EXPECT_NEAR(m.transforms()[2].transform().rotation().y(), std::sqrt(0.5), 1e-12);
  EXPECT_EQ(m.transforms()[2].transform().translation().z(), 0.1);
}

TEST(RosMessages, DiagnosticsCarryTheServersStatus) {
  msg::ServerStatus status = testing::status_message("running", 29.5f, 12.25f, 3);
  const auto m = diagnostics(9, "omnisweep-server: /omnisweep", "omnisweep", status);
  ASSERT_EQ(m.status().size(), 2u);
  EXPECT_EQ(m.status()[0].level(), 0);
  std::map<std::string, std::string> values;
  for (const auto& kv : m.status()[0].values()) values[kv.key()] = kv.value();
  EXPECT_EQ(values["fps"], "29.5");
  EXPECT_EQ(values["depth_ms"], "12.2");  // printf rounds half to even here
  EXPECT_EQ(values["dropped"], "3");
  EXPECT_EQ(m.status()[1].name(), "omnisweep-server: /omnisweep: camera 1");
  EXPECT_EQ(m.status()[1].level(), 2);
  EXPECT_EQ(m.status()[1].message(), "not delivering: no image for 2 s");
  status.state("failed");
  EXPECT_EQ(diagnostics(9, "n", "h", status).status()[0].level(), 2);
  status.state("source stalled");
  EXPECT_EQ(diagnostics(9, "n", "h", status).status()[0].level(), 1);
}

// What ROS's rmw_fastrtps sends: the XCDR1 little-endian encapsulation (00 01 00 00), then the
// fields in .msg order, strings as uint32 length (with the NUL) + bytes + NUL.
TEST(RosMessages, SerialiseAsRosCdr) {
  const std::uint8_t jpeg[] = {0xff, 0xd8, 0xff, 0xd9};
  auto m = compressed_color(make_header(3'000'000'004ull, "f"), jpeg);
  sensor_msgs::msg::CompressedImagePubSubType type;
  eprosima::fastrtps::rtps::SerializedPayload_t payload(type.getSerializedSizeProvider(&m)());
  ASSERT_TRUE(type.serialize(&m, &payload));
  const std::vector<std::uint8_t> bytes(payload.data, payload.data + payload.length);
  const std::vector<std::uint8_t>
      expected = {0,   1,   0,   0,                         // CDR_LE, options
                  3,   0,   0,   0,   4,    0,    0,    0,  // stamp sec, nanosec
                  2,   0,   0,   0,   'f',  0,    0,    0,  // frame_id "f" (+ padding)
                  27,  0,   0,   0,   'r',  'g',  'b',  '8', ';', ' ', 'j',
                  'p', 'e', 'g', ' ', 'c',  'o',  'm',  'p', 'r', 'e', 's',
                  's', 'e', 'd', ' ', 'b',  'g',  'r',  '8', 0,   0,  // format (+ padding)
                  4,   0,   0,   0,   0xff, 0xd8, 0xff, 0xd9};        // data
  EXPECT_EQ(bytes, expected);
  EXPECT_EQ(std::string(type.getName()), "sensor_msgs::msg::dds_::CompressedImage_");
}

}  // namespace
}  // namespace omnisweep::ros2
