// The region planes on the GPU (RegionPlanes, the region_*.comp kernels) against the plain C++
// version: on the box room's plain ceiling, on a noisy room with several regions and outliers in
// their support, and on a confident frame; and too small buffers are named.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

#include "server/stitch/region_planes.h"
#include "server/stitch/region_planes_scene.h"
#include "tests/support/gpu_test_support.h"
#include "tests/support/panorama_pass.h"

namespace omnisweep::stitch {
namespace {

using namespace region_test;  // NOLINT(google-build-using-namespace): the scene
using RegionPlanesGpuTest = omnisweep::testing::ValidatedGpuTest;

RegionPlaneParams params() { return RegionPlaneParams::for_width(kW); }

FloatImage run_gpu(gpu::Context& context, const Scene& s, const RegionPlaneParams& p) {
  const RegionPlanes planes(context, kW, kH, p, kMinDistance, kMaxDistance);
  return omnisweep::testing::run_panorama_pass(
      context, s.distance, s.confidence,
      [&](gpu::Sequence& seq, gpu::Buffer& distance, const gpu::Buffer& confidence) {
        planes.record(seq, distance, confidence);
      });
}

double inverse(float d) { return d > 0 ? 1.0 / d : 0.0; }

struct Agreement {
  int changed = 0;   // pixels either version changed
  int differ = 0;    // of them, those whose inverse distances differ by more than `tolerance`
  double worst = 0;  // the largest relative difference
};

Agreement compare(const Scene& s, const FloatImage& gpu, const FloatImage& cpu, double tolerance) {
  Agreement a;
  for (std::size_t i = 0; i < cpu.size(); ++i) {
    const float in = s.distance.data()[i];
    if (gpu.data()[i] == in && cpu.data()[i] == in) continue;
    ++a.changed;
    const double g = inverse(gpu.data()[i]), c = inverse(cpu.data()[i]);
    const double e = std::abs(g - c) / std::max(c, 1e-9);
    a.worst = std::max(a.worst, e);
    a.differ += e > tolerance;
  }
  return a;
}

TEST_F(RegionPlanesGpuTest, EqualsCpuOnAPlainCeiling) {
  const Scene s = make_scene(plain_ceiling);
  const FloatImage cpu =
      region_planes_cpu(s.distance, s.confidence, params(), kMinDistance, kMaxDistance);
  const Agreement a = compare(s, run_gpu(context(), s, params()), cpu, 1e-4);
  EXPECT_GT(a.changed, 2000);
  EXPECT_EQ(a.differ, 0) << "largest relative difference " << a.worst;
}

// The room with its plain ceiling, a patch of the floor and two patches of walls unconfident;
// the confident pixels' inverse distances with 1 % noise, their confidences spread over
// [0.3, 0.9], and 3 % of them wrong by up to 50 %: the RANSAC has choices to make, so the two
// versions may part where float sums differ; nearly all pixels must agree.
TEST_F(RegionPlanesGpuTest, AgreesWithCpuOnANoisyRoomWithSeveralRegions) {
  auto low = [](const Hit& h, int, int) {
    return plain_ceiling(h, 0, 0) ||
           (h.plane == 1 && std::abs(h.x - 0.5) < 1.2 && std::abs(h.y) < 1.0) ||
           (h.plane == 3 && std::abs(h.y) < 1.2 && std::abs(h.z) < 0.6) ||
           (h.plane == 4 && std::abs(h.x) < 1.5 && h.z > -0.8 && h.z < 0.9);
  };
  Scene s = make_scene(low);
  std::mt19937 rng(7);
  std::normal_distribution<float> noise(0.0f, 0.01f);
  std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
  int regions_pixels = 0;
  for (std::size_t i = 0; i < s.distance.size(); ++i) {
    if (s.low[i]) {
      ++regions_pixels;
      continue;
    }
    float v = s.truth.data()[i] * (1.0f + noise(rng));
    if (uniform(rng) < 0.03f) v *= 0.5f + uniform(rng);
    s.distance.data()[i] = 1.0f / v;
    s.confidence.data()[i] = 0.3f + 0.6f * uniform(rng);
  }
  const FloatImage cpu =
      region_planes_cpu(s.distance, s.confidence, params(), kMinDistance, kMaxDistance);
  const FloatImage gpu = run_gpu(context(), s, params());
  const Agreement a = compare(s, gpu, cpu, 1e-3);
  EXPECT_GT(a.changed, regions_pixels / 2);
  EXPECT_LE(a.differ, a.changed / 100) << "of " << a.changed << " changed pixels, largest "
                                       << "relative difference " << a.worst;
  // Both bring the regions back towards the truth.
  double before = 0, after_cpu = 0, after_gpu = 0;
  for (std::size_t i = 0; i < s.distance.size(); ++i) {
    if (!s.low[i]) continue;
    const double t = s.truth.data()[i];
    before += std::abs(inverse(s.distance.data()[i]) - t) / t;
    after_cpu += std::abs(inverse(cpu.data()[i]) - t) / t;
    after_gpu += std::abs(inverse(gpu.data()[i]) - t) / t;
  }
  EXPECT_LT(after_cpu, 0.5 * before);
  EXPECT_NEAR(after_gpu, after_cpu, 0.02 * after_cpu);
}

TEST_F(RegionPlanesGpuTest, LeavesAConfidentFrameAlone) {
  const Scene s = make_scene([](const Hit&, int, int) { return false; });
  const FloatImage out = run_gpu(context(), s, params());
  EXPECT_TRUE(std::equal(out.data(), out.data() + out.size(), s.distance.data()));
}

TEST_F(RegionPlanesGpuTest, TooSmallBuffersAndBadSettingsAreNamed) {
  const RegionPlanes planes(context(), kW, kH, params(), kMinDistance, kMaxDistance);
  gpu::Buffer small(context(), 64);
  gpu::Sequence seq(context());
  seq.begin();
  try {
    planes.record(seq, small, small);
    FAIL() << "no error for buffers of 64 bytes";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("smaller"), std::string::npos) << e.what();
  }
  RegionPlaneParams p = params();
  p.max_regions = kRegionPlaneMaxRegions + 1;
  try {
    const RegionPlanes bad(context(), kW, kH, p, kMinDistance, kMaxDistance);
    FAIL() << "no error for max_regions " << p.max_regions;
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("max_regions"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace omnisweep::stitch
