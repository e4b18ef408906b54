// Forward warp and directional inpainting on an analytic scene: a square 1 m in front of a wall
// 5 m away, seen by a pinhole camera and warped to a camera 0.3 m to the side.
#include "omnisweep/reproject/forward_warp.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "omnisweep/gpu/buffer.h"
#include "tests/support/gpu_test_support.h"
#include "tests/support/test_support.h"

namespace omnisweep::reproject {
namespace {

using omnisweep::testing::ValidatedGpuTest;
using ForwardWarpTest = ValidatedGpuTest;

constexpr int kSize = 96;
constexpr double kFocal = 80.0, kCentre = 47.5;
constexpr double kWall = 5.0, kSquare = 1.0, kHalfSide = 0.2;

// Distance along `ray` from `origin` to the scene; *near says whether the square was hit.
double cast(const Eigen::Vector3d& origin, const Eigen::Vector3d& ray, bool* near) {
  const double t_square = (kSquare - origin.z()) / ray.z();
  const Eigen::Vector3d hit = origin + t_square * ray;
  *near = t_square > 0 && std::abs(hit.x()) < kHalfSide && std::abs(hit.y()) < kHalfSide;
  return *near ? t_square : (kWall - origin.z()) / ray.z();
}

Eigen::Vector3d pixel_ray(int u, int v) {
  return Eigen::Vector3d((u - kCentre) / kFocal, (v - kCentre) / kFocal, 1).normalized();
}

// The source camera's distance map of the scene, on the GPU.
gpu::Buffer source_distance(gpu::Context& context) {
  std::vector<float> distance(std::size_t(kSize) * kSize);
  bool near;
  for (int v = 0; v < kSize; ++v)
    for (int u = 0; u < kSize; ++u)
      distance[v * kSize + u] = float(cast(Eigen::Vector3d::Zero(), pixel_ray(u, v), &near));
  gpu::Buffer buffer(context, distance.size() * 4);
  buffer.upload(std::span<const float>(distance));
  return buffer;
}

TEST(WarpOptions, CheckNamesTheFieldAndItsValue) {
  EXPECT_NO_THROW(WarpOptions{}.check());
  auto message = [](const WarpOptions& o) {
    return omnisweep::testing::error_message<std::invalid_argument>([&] { o.check(); });
  };
  WarpOptions o;
  o.max_splat = 0.5;
  EXPECT_NE(message(o).find("WarpOptions.max_splat = 0.5"), std::string::npos) << message(o);
  EXPECT_NE(message(o).find("at least 1"), std::string::npos) << message(o);
  o = {};
  o.occlusion_tolerance = 1;
  EXPECT_NE(message(o).find("WarpOptions.occlusion_tolerance = 1"), std::string::npos);
  o = {};
  o.min_distance = 0;
  EXPECT_NE(message(o).find("WarpOptions.min_distance = 0"), std::string::npos);
  o = {};
  o.inpaint_passes = 2000;
  EXPECT_NE(message(o).find("WarpOptions.inpaint_passes = 2000"), std::string::npos);
}

TEST_F(ForwardWarpTest, NearSurfaceWinsAndHolesFillFromTheBackground) {
  const CameraModel<double> pinhole = PinholeCamera<double>({kFocal, kFocal, kCentre, kCentre});
  // The target sits 0.3 m to the right: target_from_source moves points 0.3 m to the left.
  const Rigid3d target_from_source(Eigen::Quaterniond::Identity(), Eigen::Vector3d(-0.3, 0, 0));
  const GpuCamera source = pack_camera(pinhole, kSize, kSize, Rigid3d());
  const GpuCamera target = pack_camera(pinhole, kSize, kSize, target_from_source);

  const gpu::Buffer distance_buffer = source_distance(context());
  bool near;

  // Without inpainting: the holes themselves.
  ForwardWarper raw(context(), source, target,
                    {.min_distance = 0.55, .max_distance = 100, .inpaint_passes = 0});
  ForwardWarper filled(context(), source, target,
                       {.min_distance = 0.55, .max_distance = 100, .inpaint_passes = 32});
  gpu::Sequence seq(context());
  seq.begin();
  raw.record(seq, distance_buffer);
  filled.record(seq, distance_buffer);
  seq.submit_and_wait();
  const FloatImage holes = raw.download(), result = filled.download();

  long near_pixels = 0, near_ok = 0, disoccluded = 0, filled_from_wall = 0, left_open = 0;
  for (int v = 2; v < kSize - 2; ++v) {
    for (int u = 2; u < kSize - 2; ++u) {
      const double truth = cast(Eigen::Vector3d(0.3, 0, 0), pixel_ray(u, v), &near);
      if (near) {  // the z-buffer must keep the square where the wall lands too
        ++near_pixels;
        near_ok += std::abs(holes(u, v) - truth) < 0.05 * truth;
      } else if (holes(u, v) == 0.0f && std::abs(u - kCentre) < 30 && std::abs(v - kCentre) < 15) {
        ++disoccluded;  // the wall behind the square, which the source never saw
        if (result(u, v) == 0.0f) {
          ++left_open;
        } else {
          filled_from_wall += std::abs(result(u, v) - truth) < 0.1 * truth;
        }
      }
    }
  }
  std::cout << near_pixels << " square pixels, " << near_ok << " kept by the z-buffer; "
            << disoccluded << " disoccluded, " << filled_from_wall
            << " filled with the wall's distance, " << left_open << " left open\n";
  EXPECT_GT(near_pixels, 300);
  EXPECT_GE(double(near_ok) / near_pixels, 0.97);
  EXPECT_GT(disoccluded, 100);
  EXPECT_EQ(left_open, 0);
  EXPECT_GE(double(filled_from_wall) / disoccluded, 0.97);
}

TEST_F(ForwardWarpTest, EquirectangularTargetWrapsAround) {
  // A fisheye-free check of the panorama target: a pinhole source looking along +z, warped to a
  // panorama at the same place, lands around the panorama's centre column.
  const CameraModel<double> pinhole = PinholeCamera<double>({kFocal, kFocal, kCentre, kCentre});
  const GpuCamera source = pack_camera(pinhole, kSize, kSize, Rigid3d());
  const GpuCamera target = pack_equirectangular(256, 128, Rigid3d());
  std::vector<float> distance(std::size_t(kSize) * kSize, 2.0f);
  gpu::Buffer distance_buffer(context(), distance.size() * 4);
  distance_buffer.upload(std::span<const float>(distance));
  ForwardWarper warper(context(), source, target, {.inpaint_passes = 0});
  gpu::Sequence seq(context());
  seq.begin();
  warper.record(seq, distance_buffer);
  seq.submit_and_wait();
  const FloatImage pano = warper.download();
  EXPECT_NEAR(pano(128, 64), 2.0f, 1e-3f);  // straight ahead
  EXPECT_EQ(pano(0, 64), 0.0f);             // behind: nothing
  EXPECT_EQ(pano(128, 2), 0.0f);            // straight up: nothing
}

// Directional inpainting pass by pass on the CPU, as ALGORITHM.md §5 step 2 states it: the
// reference for the GPU kernel, which runs up to 8 passes per dispatch in shared-memory tiles.
struct Direction {
  std::uint32_t codes;
  float weight0, weight1;
  std::uint32_t unused;
};

std::vector<std::uint32_t> inpaint_cpu(std::vector<std::uint32_t> bits,
                                       const std::vector<Direction>& directions, int width,
                                       int height, bool wrap, int passes) {
  constexpr std::uint32_t kEmpty = 0xffffffffu;
  static const int kOffsets[8][2] = {{1, 0},  {1, 1},   {0, 1},  {-1, 1},
                                     {-1, 0}, {-1, -1}, {0, -1}, {1, -1}};
  for (int pass = 0; pass < passes; ++pass) {
    std::vector<std::uint32_t> next = bits;
    for (int y = 0; y < height; ++y) {
      for (int x = 0; x < width; ++x) {
        const int i = y * width + x;
        if (bits[i] != kEmpty) continue;
        const Direction& d = directions[i];
        float sum = 0, total = 0;
        for (int k = 0; k < 2; ++k) {
          const std::uint32_t code = (d.codes >> (8 * k)) & 0xffu;
          if (code > 7) continue;
          int nx = x + kOffsets[code][0];
          const int ny = y + kOffsets[code][1];
          if (wrap) nx = (nx + width) % width;
          if (nx < 0 || ny < 0 || nx >= width || ny >= height) continue;
          const std::uint32_t v = bits[ny * width + nx];
          if (v == kEmpty) continue;
          float value;
          std::memcpy(&value, &v, 4);
          const float w = k == 0 ? d.weight0 : d.weight1;
          sum += w * value;
          total += w;
        }
        if (total > 0) {
          const float value = sum / total;
          std::memcpy(&next[i], &value, 4);
        }
      }
    }
    bits.swap(next);
  }
  return bits;
}

// Pixels where inpainted maps (float bits, 0xffffffff empty) disagree: one empty and the other
// not, or values more than 1e-5 apart relative (fused multiply-adds may round apart).
long pixels_apart(const std::vector<std::uint32_t>& gpu, const std::vector<std::uint32_t>& cpu) {
  long differ = 0;
  for (std::size_t i = 0; i < cpu.size(); ++i) {
    if ((gpu[i] == 0xffffffffu) != (cpu[i] == 0xffffffffu)) {
      ++differ;
      continue;
    }
    if (cpu[i] == 0xffffffffu) continue;
    float a, b;
    std::memcpy(&a, &gpu[i], 4);
    std::memcpy(&b, &cpu[i], 4);
    differ += std::abs(a - b) > 1e-5f * std::abs(b);
  }
  return differ;
}

// What the CPU inpaints from: the warp's holes (no inpainting) and its background directions.
struct RawWarp {
  std::vector<std::uint32_t> holes;
  std::vector<Direction> directions;
};
RawWarp raw_warp(gpu::Context& context, const GpuCamera& source, const GpuCamera& target,
                 const gpu::Buffer& distance) {
  ForwardWarper raw(context, source, target, {.inpaint_passes = 0});
  gpu::Sequence seq(context);
  seq.begin();
  raw.record(seq, distance);
  seq.submit_and_wait();
  return {raw.result().download<std::uint32_t>(), raw.directions().download<Direction>()};
}

// The tiled kernel against the CPU, pass counts across dispatch boundaries (8 passes each), on a
// pinhole target and on a panorama that wraps around and is no multiple of the tile size.
TEST_F(ForwardWarpTest, TiledInpaintingMatchesPassByPassInpainting) {
  const CameraModel<double> pinhole = PinholeCamera<double>({kFocal, kFocal, kCentre, kCentre});
  const Rigid3d target_from_source(Eigen::Quaterniond::Identity(), Eigen::Vector3d(-0.3, 0, 0));
  const GpuCamera source = pack_camera(pinhole, kSize, kSize, Rigid3d());
  const gpu::Buffer distance_buffer = source_distance(context());
  const GpuCamera targets[2] = {pack_camera(pinhole, kSize, kSize, target_from_source),
                                pack_equirectangular(200, 100, target_from_source)};
  for (const GpuCamera& target : targets) {
    const bool wrap = target.model == std::uint32_t(GpuModel::kEquirectangular);
    const int w = int(target.width), h = int(target.height);
    const auto [holes, directions] = raw_warp(context(), source, target, distance_buffer);
    gpu::Sequence seq(context());
    for (const int passes : {1, 5, 8, 9, 16, 23}) {
      ForwardWarper warper(context(), source, target, {.inpaint_passes = passes});
      seq.begin();
      warper.record(seq, distance_buffer);
      seq.submit_and_wait();
      const auto gpu = warper.result().download<std::uint32_t>();
      const auto cpu = inpaint_cpu(holes, directions, w, h, wrap, passes);
      long filled = 0;
      for (std::size_t i = 0; i < cpu.size(); ++i)
        filled += holes[i] == 0xffffffffu && cpu[i] != 0xffffffffu;
      const long differ = pixels_apart(gpu, cpu);
      EXPECT_EQ(differ, 0) << (wrap ? "panorama" : "pinhole") << ", " << passes << " passes";
      EXPECT_GT(filled, 0) << passes << " passes filled nothing: the check proves nothing";
    }
  }
}

// Adaptive inpainting in batches of any size (a dispatch per batch, its passes not a multiple of
// the 8 a dispatch holds) equals the CPU's passes, also right after the same warper ran on
// another map: the tile statuses one dispatch leaves for the next are read only by the next.
TEST_F(ForwardWarpTest, AdaptiveInpaintingInAnyBatchMatchesTheCpu) {
  const CameraModel<double> pinhole = PinholeCamera<double>({kFocal, kFocal, kCentre, kCentre});
  const Rigid3d target_from_source(Eigen::Quaterniond::Identity(), Eigen::Vector3d(-0.3, 0, 0));
  const GpuCamera source = pack_camera(pinhole, kSize, kSize, Rigid3d());
  const GpuCamera target = pack_camera(pinhole, kSize, kSize, target_from_source);
  const gpu::Buffer distance_buffer = source_distance(context());
  const auto [holes, directions] = raw_warp(context(), source, target, distance_buffer);
  gpu::Sequence seq(context());
  // A wall 5 m away everywhere: no disocclusion, so its run leaves nearly every tile settled.
  const std::vector<float> wall(std::size_t(kSize) * kSize, 5.0f);
  gpu::Buffer wall_buffer(context(), wall.size() * 4);
  wall_buffer.upload(std::span<const float>(wall));
  ForwardWarper warper(context(), source, target, {.inpaint_passes = 0});
  for (const int batch : {8, 3, 5, 1, 8}) {
    warper.set_inpaint_passes(16);  // two dispatches: both status sets written
    seq.begin();
    warper.record(seq, wall_buffer);
    seq.submit_and_wait();
    double ms = 0;
    seq.begin();
    warper.record_warp(seq, distance_buffer);
    const int passes = warper.inpaint_until_filled(seq, 40, batch, &ms);
    const auto gpu = warper.result().download<std::uint32_t>();
    const auto cpu = inpaint_cpu(holes, directions, kSize, kSize, false, passes);
    EXPECT_EQ(pixels_apart(gpu, cpu), 0) << "batches of " << batch << ", " << passes << " passes";
  }
}

// Layers (the stitcher's references) in each dispatch give each layer what a warper of its own
// gives, bit for bit; layers of different sizes, or colour with layers, are refused.
TEST_F(ForwardWarpTest, LayersWarpLikeSeparateWarpers) {
  const CameraModel<double> pinhole = PinholeCamera<double>({kFocal, kFocal, kCentre, kCentre});
  const GpuCamera source = pack_camera(pinhole, kSize, kSize, Rigid3d());
  const std::vector<Eigen::Vector3d> shifts = {{-0.3, 0, 0}, {0.2, 0.1, 0}};
  const WarpOptions options{.min_distance = 0.55, .max_distance = 100, .inpaint_passes = 32};
  const gpu::Buffer one = source_distance(context());
  // Both layers warp the same map: the sources side by side.
  gpu::Buffer both(context(), 2 * one.size());
  const std::vector<float> map = one.download<float>();
  both.upload(std::span<const float>(map));
  both.upload(std::span<const float>(map), one.size());

  std::vector<WarpLayer> layers;
  std::vector<FloatImage> alone;
  for (const Eigen::Vector3d& shift : shifts) {
    const GpuCamera target =
        pack_camera(pinhole, kSize, kSize, Rigid3d(Eigen::Quaterniond::Identity(), shift));
    layers.push_back({source, target});
    ForwardWarper warper(context(), source, target, options);
    gpu::Sequence seq(context());
    seq.begin();
    warper.record(seq, one);
    seq.submit_and_wait();
    alone.push_back(warper.download());
  }
  ForwardWarper layered(context(), layers, options);
  EXPECT_EQ(layered.layers(), 2);
  gpu::Sequence seq(context());
  seq.begin();
  layered.record(seq, both);
  seq.submit_and_wait();
  for (int l = 0; l < 2; ++l) {
    const FloatImage got = layered.download(l);
    EXPECT_EQ(std::memcmp(got.data(), alone[l].data(), got.size() * 4), 0) << "layer " << l;
  }
  EXPECT_THROW(layered.download(2), std::out_of_range);
  EXPECT_THROW(layered.set_target(layers[0].target), std::logic_error);

  layers[1].target.width = kSize / 2;
  EXPECT_THROW(ForwardWarper(context(), layers, options), std::invalid_argument);
  WarpOptions color = options;
  color.color = true;
  layers[1].target.width = kSize;
  EXPECT_THROW(ForwardWarper(context(), layers, color), std::invalid_argument);
}

}  // namespace
}  // namespace omnisweep::reproject
