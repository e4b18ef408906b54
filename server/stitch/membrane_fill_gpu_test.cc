// The membrane fill on the GPU (MembraneFill, the membrane_*.comp kernels) against
// membrane_fill_cpu: a wavy room whose unconfident regions are a cap at the pole (whole rows:
// cyclic line solves), a region across the seam (runs cut by the rows), a random band (runs
// that differ from row to row) and a blob too small to fill; a frame without a known cell; and too
// small buffers are named.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "server/stitch/membrane_fill.h"
#include "tests/support/gpu_test_support.h"
#include "tests/support/panorama_pass.h"
#include "tests/support/test_support.h"

namespace omnisweep::stitch {
namespace {

using MembraneFillGpuTest = omnisweep::testing::ValidatedGpuTest;

constexpr int kW = 512, kH = 256;
constexpr double kMinDistance = 0.5, kMaxDistance = 100.0;

struct Scene {
  FloatImage distance{kW, kH}, confidence{kW, kH};
  static bool in_blob(int x, int y) { return x >= 300 && x < 306 && y >= 100 && y < 106; }
  // A band below the horizon whose cells are unconfident at random, two in three (above the
  // percolation threshold: one component of many runs that differ from row to row).
  static bool in_bands(int x, int y) {
    const unsigned cell = unsigned(x / 2) * 2654435761u ^ unsigned(y / 2) * 40503u;
    return y >= 110 && y < 146 && (cell >> 13) % 3 != 0;
  }
  static bool plain(int x, int y) {
    return y < 84 || ((x < 60 || x >= kW - 90) && y >= 150 && y < 230) || in_bands(x, y) ||
           in_blob(x, y);
  }
  Scene() {
    for (int y = 0; y < kH; ++y) {
      for (int x = 0; x < kW; ++x) {
        const double phi = (x + 0.5) / kW * 2 * std::numbers::pi;
        const double wavy = 0.4 + 0.15 * std::sin(3 * phi) + 0.1 * std::cos(7.0 * y / kH);
        distance(x, y) = plain(x, y) ? 3.0f : float(1.0 / wavy);
        // The confident pixels mostly well above the thresholds, a few just around them.
        confidence(x, y) = plain(x, y) ? 0.02f : ((x * 7 + y * 3) % 11 == 0 ? 0.1f : 0.9f);
      }
    }
  }
};

MembraneFillParams params() {
  MembraneFillParams p = MembraneFillParams::for_width(kW);  // cells of 2 pixels: 256 x 128
  p.min_cells = 200;
  return p;
}

FloatImage run_gpu(gpu::Context& context, const Scene& s, const MembraneFillParams& p) {
  const MembraneFill fill(context, kW, kH, p, kMinDistance, kMaxDistance);
  return omnisweep::testing::run_panorama_pass(
      context, s.distance, s.confidence,
      [&](gpu::Sequence& seq, gpu::Buffer& distance, const gpu::Buffer& confidence) {
        fill.record(seq, distance, confidence);
      });
}

TEST_F(MembraneFillGpuTest, EqualsCpu) {
  const Scene s;
  const FloatImage gpu = run_gpu(context(), s, params());
  const FloatImage cpu =
      membrane_fill_cpu(s.distance, s.confidence, params(), kMinDistance, kMaxDistance);
  double worst = 0, mean = 0;
  int filled = 0;
  for (int y = 0; y < kH; ++y) {
    for (int x = 0; x < kW; ++x) {
      const bool changed = cpu(x, y) != s.distance(x, y);
      ASSERT_EQ(changed, gpu(x, y) != s.distance(x, y)) << "pixel " << x << ", " << y;
      if (!changed) continue;
      const double difference = std::abs(1.0 / gpu(x, y) - 1.0 / cpu(x, y));
      worst = std::max(worst, difference);
      mean += difference;
      ++filled;
    }
  }
  mean /= std::max(filled, 1);
  std::cout << filled << " pixels filled; GPU - CPU: mean " << mean << ", largest " << worst
            << " m^-1\n";
  EXPECT_GT(filled, 60000);  // the cap, the seam's region and the band, not the blob
  EXPECT_EQ(gpu(302, 102), 3.0f);
  // Measured here: 2.1e-4 on average, 9.1e-4 at most, nearly all of it in the cap: in float, the
  // residual of a row by the pole cancels to about 4e-6 and its ring's lowest mode (1e-4 of the
  // diagonal) makes that 1e-4 or more of the field. The region across the seam alone agrees to
  // 1.2e-6 on average.
  EXPECT_LT(mean, 1e-3);
  EXPECT_LT(worst, 3e-3);
}

TEST_F(MembraneFillGpuTest, NothingKnownNothingFilled) {
  Scene s;
  for (float& c : s.confidence.pixels()) c = 0.0f;
  const FloatImage gpu = run_gpu(context(), s, params());
  EXPECT_TRUE(std::equal(gpu.pixels().begin(), gpu.pixels().end(), s.distance.pixels().begin()));
}

TEST_F(MembraneFillGpuTest, BadInputIsNamed) {
  EXPECT_THROW(MembraneFill(context(), 30, 15, params(), kMinDistance, kMaxDistance),
               std::invalid_argument);
  MembraneFillParams direct = params();
  direct.solver = MembraneSolver::kDirect;
  EXPECT_THROW(MembraneFill(context(), kW, kH, direct, kMinDistance, kMaxDistance),
               std::invalid_argument);
  const MembraneFill fill(context(), kW, kH, params(), kMinDistance, kMaxDistance);
  gpu::Buffer small(context(), 64), full(context(), vk::DeviceSize(kW) * kH * 4);
  gpu::Sequence seq(context());
  seq.begin();
  EXPECT_EQ(omnisweep::testing::error_message<std::invalid_argument>(
                [&] { fill.record(seq, small, full); }),
            "membrane fill: the panorama buffers are smaller than its size");
}

}  // namespace
}  // namespace omnisweep::stitch
