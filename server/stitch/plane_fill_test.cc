// The plane fill: the GPU kernels against the plain C++ version, and what it promises: a floor
// whose unconfident distances were pulled far comes back onto its plane, a pixel halfway to the
// threshold gets half of it, confident pixels are left alone, and a bad setting is named.
#include "server/stitch/plane_fill.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "omnisweep/reproject/gpu_camera.h"
#include "server/stitch/stitcher.h"
#include "tests/support/gpu_test_support.h"

namespace omnisweep::stitch {
namespace {

using PlaneFillTest = omnisweep::testing::ValidatedGpuTest;

constexpr int kW = 256, kH = 128;
constexpr double kMinDistance = 0.55, kMaxDistance = 100.0;
constexpr std::size_t kHalfway = std::size_t(kH * 13 / 16) * kW + 80;  // a band pixel

struct Scene {
  FloatImage truth;  // inverse distance
  FloatImage distance;
  FloatImage confidence;
  Rgb8Image color;
  std::vector<bool> band;  // the unconfident floor pixels
};

// A floor 1.5 m below the viewpoint (the lower half, a dark colour) and a wall at 4 m all around
// above it (a light colour). Confidences are 0.3-1 except in a band of the floor, where they are
// 0-0.002 and the distance was pulled out to the wall's. A hole (no distance) at one pixel. With
// `decoys`, every third floor pixel outside the band is confident at the wall's distance instead
// (like-coloured support on another surface, as kaist-rig's white slats below its white ceiling).
Scene make_scene(bool decoys = false) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> confident(0.3f, 1.0f), unconfident(0.0f, 0.002f);
  std::normal_distribution<float> noise(0.0f, 0.002f);
  std::uniform_int_distribution<int> jitter(-2, 2);
  Scene s{FloatImage(kW, kH), FloatImage(kW, kH), FloatImage(kW, kH), Rgb8Image(kW, kH),
          std::vector<bool>(std::size_t(kW) * kH, false)};
  for (int y = 0; y < kH; ++y) {
    const double phi = std::numbers::pi * (y + 0.5) / kH;
    for (int x = 0; x < kW; ++x) {
      const std::size_t i = std::size_t(y) * kW + x;
      const bool floor = std::cos(phi) < -0.4;  // the floor nearer than the wall
      const float v = floor ? float(-std::cos(phi) / 1.5) : 0.25f;
      s.truth.data()[i] = v;
      const bool band = floor && y >= kH * 3 / 4 && y < kH * 7 / 8 && x >= 40 && x < 120;
      s.band[i] = band;
      const bool decoy = decoys && floor && !band && (x + y) % 3 == 0;
      s.distance.data()[i] = 1.0f / (band || decoy ? 0.25f : v + noise(rng));
      s.confidence.data()[i] = band ? unconfident(rng) : confident(rng);
      for (int c = 0; c < 3; ++c)
        s.color.data()[3 * i + c] = std::uint8_t((floor ? 70 : 190) + 10 * c + jitter(rng));
    }
  }
  s.distance.data()[std::size_t(kH - 10) * kW + 60] = 0.0f;
  s.confidence.data()[kHalfway] = 0.025f;  // halfway to the tests' threshold of 0.05
  return s;
}

FloatImage run_gpu(gpu::Context& context, const Scene& s, double fill_below) {
  const vk::DeviceSize bytes = vk::DeviceSize(kW) * kH * 4;
  gpu::Buffer color(context, bytes), distance(context, bytes), confidence(context, bytes),
      out(context, bytes);
  std::vector<std::uint32_t> packed(std::size_t(kW) * kH);
  reproject::pack_rgba8(s.color, packed);
  color.upload(std::span<const std::uint32_t>(packed));
  distance.upload(s.distance.data(), bytes);
  confidence.upload(s.confidence.data(), bytes);
  const PlaneFill fill(context, kW, kH, fill_below, kMinDistance, kMaxDistance);
  gpu::Sequence seq(context);
  seq.begin();
  fill.record(seq, color, distance, confidence, out);
  seq.submit_and_wait();
  FloatImage result(kW, kH);
  out.download(result.data(), bytes);
  return result;
}

double inverse(float d) { return d > 0 ? 1.0 / d : 0.0; }

// The largest inverse-distance difference (1/m) between `gpu` and plane_fill_cpu on `s`.
double worst_cpu_difference(const Scene& s, const FloatImage& gpu) {
  const FloatImage cpu =
      plane_fill_cpu(s.color, s.distance, s.confidence, 0.05, kMinDistance, kMaxDistance);
  double worst = 0;
  for (std::size_t i = 0; i < cpu.size(); ++i)
    worst = std::max(worst, std::abs(inverse(gpu.data()[i]) - inverse(cpu.data()[i])));
  return worst;
}

// The band's pixels that are measured: those with a distance, less the one halfway to the
// threshold.
bool measured(const Scene& s, std::size_t i) {
  return s.band[i] && s.distance.data()[i] != 0 && i != kHalfway;
}

int measured_pixels(const Scene& s) {
  int n = 0;
  for (std::size_t i = 0; i < s.band.size(); ++i) n += measured(s, i) ? 1 : 0;
  return n;
}

// The MAE (1/m) of `distance` against the truth over the measured band pixels.
double band_mae(const Scene& s, const FloatImage& distance) {
  double sum = 0;
  for (std::size_t i = 0; i < s.band.size(); ++i)
    if (measured(s, i)) sum += std::abs(inverse(distance.data()[i]) - s.truth.data()[i]);
  return sum / measured_pixels(s);
}

TEST_F(PlaneFillTest, EqualsCpu) {
  const Scene s = make_scene();
  EXPECT_LT(worst_cpu_difference(s, run_gpu(context(), s, 0.05)), 1e-4)
      << "largest inverse-distance difference, 1/m";
}

TEST_F(PlaneFillTest, PutsAPulledFloorBackOnItsPlane) {
  const Scene s = make_scene();
  const FloatImage out = run_gpu(context(), s, 0.05);
  ASSERT_GT(measured_pixels(s), 1000);
  const double before = band_mae(s, s.distance);
  EXPECT_GT(before, 0.3);
  EXPECT_LT(band_mae(s, out), 0.03)
      << "the band's MAE after the fill, 1/m (before " << before << ")";
  for (std::size_t i = 0; i < out.size(); ++i) {
    if (!s.band[i]) {
      ASSERT_EQ(out.data()[i], s.distance.data()[i]) << "pixel " << i;
    }
  }
  ASSERT_TRUE(s.band[kHalfway]);
  const double pulled = inverse(s.distance.data()[kHalfway]), truth = s.truth.data()[kHalfway];
  EXPECT_NEAR(inverse(out.data()[kHalfway]), 0.5 * (pulled + truth), 0.03)
      << "pulled " << pulled << ", plane " << truth;
  // Below no confidence (0): nothing changes.
  const FloatImage none = run_gpu(context(), s, 0.0);
  for (std::size_t i = 0; i < none.size(); ++i)
    ASSERT_EQ(none.data()[i], s.distance.data()[i]) << "pixel " << i;
}

// The refits: a third of the floor's support lies at the wall's distance with the floor's colour;
// one least-squares fit puts the band a third of the way to the wall (MAE 0.11 m^-1 without
// refits), the refits drop the decoys and keep it near the floor (0.04 with two).
TEST_F(PlaneFillTest, RefitsDropLikeColouredSupportOnAnotherSurface) {
  const Scene s = make_scene(true);
  const FloatImage out = run_gpu(context(), s, 0.05);
  ASSERT_GT(measured_pixels(s), 1000);
  EXPECT_LT(band_mae(s, out), 0.05) << "the band's MAE after the fill, 1/m";
  EXPECT_LT(worst_cpu_difference(s, out), 1e-4)
      << "largest inverse-distance difference from the CPU, 1/m";
}

TEST(PlaneFillOptions, BadSettingIsNamed) {
  StitchOptions options;
  options.plane_fill = 1.0;
  try {
    options.check();
    FAIL() << "plane_fill 1 was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("plane_fill"), std::string::npos) << e.what();
  }
  options.plane_fill = -0.1;
  EXPECT_THROW(options.check(), std::invalid_argument);
  options.plane_fill = 0.05;
  EXPECT_NO_THROW(options.check());
}

}  // namespace
}  // namespace omnisweep::stitch
