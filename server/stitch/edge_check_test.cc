// The edge check: the GPU kernels against the plain C++ version, and what it promises: the
// confidence of a distance carried across a plain surface (a blob at a pole's distance on the
// ceiling beside it) falls to a tenth, across the panorama's seam too, while true edges, where
// colour steps with the distance, and pixels out of reach keep theirs; a bad setting is named.
#include "server/stitch/edge_check.h"

#include <gtest/gtest.h>

#include <random>

#include "omnisweep/reproject/gpu_camera.h"
#include "tests/support/gpu_test_support.h"

namespace omnisweep::stitch {
namespace {

using EdgeCheckTest = omnisweep::testing::ValidatedGpuTest;

constexpr int kW = 512, kH = 256;  // blocks of 2 pixels, 3 blocks of reach

struct Scene {
  Rgb8Image color{kW, kH};
  FloatImage distance{kW, kH};
  FloatImage confidence{kW, kH};
};

bool in_blob(int x, int y) { return y >= 40 && y <= 50 && x >= 106 && x <= 115; }
bool in_seam_blob(int x, int y) { return y >= 20 && y <= 26 && x <= 4; }

// A plain ceiling at 4 m over the upper half, a darker floor at 2 m below, a red pole at 1 m in
// columns 100-105; colours within 2 levels and inverse distances within 0.005 m^-1 of their
// surface's (no steps within surfaces). Two blobs of ceiling colour at the pole's distance: one
// beside the pole, one on the seam (columns 0-4). One hole (no distance) in the ceiling.
Scene make_scene() {
  std::mt19937 rng(11);
  std::uniform_int_distribution<int> level(-2, 2);
  std::uniform_real_distribution<float> jitter(-0.0025f, 0.0025f), confident(0.3f, 1.0f);
  Scene s;
  for (int y = 0; y < kH; ++y) {
    for (int x = 0; x < kW; ++x) {
      const bool pole = x >= 100 && x <= 105, ceiling = y < kH / 2;
      const std::array<int, 3> rgb = pole      ? std::array{200, 50, 50}
                                     : ceiling ? std::array{120, 130, 140}
                                               : std::array{60, 60, 40};
      for (int c = 0; c < 3; ++c) s.color(x, y, c) = std::uint8_t(rgb[c] + level(rng));
      const float inverse = pole || in_blob(x, y) || in_seam_blob(x, y) ? 1.0f
                            : ceiling                                   ? 0.25f
                                                                        : 0.5f;
      s.distance(x, y) = 1.0f / (inverse + jitter(rng));
      s.confidence(x, y) = confident(rng);
    }
  }
  s.distance(300, 60) = 0.0f;
  return s;
}

FloatImage run_gpu(gpu::Context& context, const Scene& s) {
  const vk::DeviceSize bytes = vk::DeviceSize(kW) * kH * 4;
  gpu::Buffer color(context, bytes), distance(context, bytes), confidence(context, bytes);
  std::vector<std::uint32_t> packed(std::size_t(kW) * kH);
  reproject::pack_rgba8(s.color, packed);
  color.upload(std::span<const std::uint32_t>(packed));
  distance.upload(s.distance.data(), bytes);
  confidence.upload(s.confidence.data(), bytes);
  const EdgeCheck check(context, kW, kH, EdgeCheckParams::for_width(kW));
  gpu::Sequence seq(context);
  seq.begin();
  check.record(seq, color, distance, confidence);
  seq.submit_and_wait();
  FloatImage result(kW, kH);
  confidence.download(result.data(), bytes);
  return result;
}

TEST_F(EdgeCheckTest, EqualsCpu) {
  const Scene s = make_scene();
  const FloatImage gpu = run_gpu(context(), s);
  const FloatImage cpu =
      edge_check_cpu(s.color, s.distance, s.confidence, EdgeCheckParams::for_width(kW));
  int lowered = 0;
  for (int y = 0; y < kH; ++y) {
    for (int x = 0; x < kW; ++x) {
      ASSERT_EQ(gpu(x, y), cpu(x, y)) << "pixel " << x << ", " << y;
      lowered += cpu(x, y) < s.confidence(x, y) ? 1 : 0;
    }
  }
  EXPECT_GT(lowered, 200);  // the check did something to compare
}

TEST_F(EdgeCheckTest, LowersCarriedDistancesOnly) {
  const Scene s = make_scene();
  const FloatImage out = run_gpu(context(), s);
  EXPECT_EQ(EdgeCheckParams::for_width(kW).block, 2);
  for (int y = 0; y < kH; ++y) {
    for (int x = 0; x < kW; ++x) {
      if (in_blob(x, y) || in_seam_blob(x, y)) {
        ASSERT_FLOAT_EQ(out(x, y), 0.1f * s.confidence(x, y)) << "blob pixel " << x << ", " << y;
      }
    }
  }
  // Across the seam: the ceiling two columns left of column 0 is within reach, 20 columns is not.
  EXPECT_FLOAT_EQ(out(kW - 2, 23), 0.1f * s.confidence(kW - 2, 23));
  EXPECT_EQ(out(kW - 20, 23), s.confidence(kW - 20, 23));
  // True edges (the pole's sides, the horizon), plain surfaces and the hole keep theirs: every
  // pixel farther than the reach (3 blocks of 2 pixels, plus the block) from both blobs.
  const auto far_from_blobs = [](int x, int y) {
    const bool near_blob = y >= 40 - 8 && y <= 50 + 8 && x >= 106 - 8 && x <= 115 + 8;
    const bool near_seam = y >= 20 - 8 && y <= 26 + 8 && (x <= 4 + 8 || x >= kW - 8);
    return !near_blob && !near_seam;
  };
  for (int y = 0; y < kH; ++y) {
    for (int x = 0; x < kW; ++x) {
      if (far_from_blobs(x, y)) {
        ASSERT_EQ(out(x, y), s.confidence(x, y)) << "pixel " << x << ", " << y;
      }
    }
  }
}

TEST_F(EdgeCheckTest, NamesABadSetting) {
  EdgeCheckParams bad;
  bad.factor = 1.5;
  EXPECT_THROW(EdgeCheck(context(), kW, kH, bad), std::invalid_argument);
  const Scene s = make_scene();
  EXPECT_THROW(edge_check_cpu(s.color, s.distance, s.confidence, bad), std::invalid_argument);
  EXPECT_THROW(edge_check_cpu(s.color, FloatImage(kW / 2, kH), s.confidence, EdgeCheckParams()),
               std::invalid_argument);
}

}  // namespace
}  // namespace omnisweep::stitch
