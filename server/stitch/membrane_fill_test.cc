// The membrane fill's CPU reference: a plane's inverse distance solves its equation, so a plain
// ceiling inside a confident rim comes back as the plane, whatever the filter had left there.
#include "server/stitch/membrane_fill.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>

#include "tests/support/test_support.h"

namespace omnisweep::stitch {
namespace {

constexpr int kW = 512, kH = 256;

// A tilted ceiling: 1/D = a . r for the ray of pixel (x, y), the polar angle from the top row.
double plane_inverse(int x, int y) {
  const double theta = (y + 0.5) / kH * std::numbers::pi;
  const double phi = (x + 0.5) / kW * 2 * std::numbers::pi;
  return 0.1 * std::sin(theta) * std::cos(phi) - 0.05 * std::sin(theta) * std::sin(phi) +
         std::cos(theta);
}

struct Scene {
  FloatImage distance{kW, kH}, confidence{kW, kH};
  // The cap within 59 degrees of the top (84 rows, whole cells): unconfident, at a wrong 3 m; a
  // blob of 6 x 6 pixels near the horizon: unconfident too, but too small to fill; elsewhere the
  // plane (or 50 m where it faces away), confident.
  static bool in_cap(int y) { return y < 84; }
  static bool in_blob(int x, int y) { return x >= 300 && x < 306 && y >= 100 && y < 106; }
  Scene() {
    for (int y = 0; y < kH; ++y) {
      for (int x = 0; x < kW; ++x) {
        const double v = plane_inverse(x, y);
        const bool plain = in_cap(y) || in_blob(x, y);
        distance(x, y) = plain ? 3.0f : float(v > 0.02 ? 1.0 / v : 50.0);
        confidence(x, y) = plain ? 0.0f : 0.9f;
      }
    }
  }
};

MembraneFillParams test_params() {
  MembraneFillParams p = MembraneFillParams::for_width(kW);  // cells of 2 pixels: 256 x 128
  p.min_cells = 200;
  return p;
}

TEST(MembraneFillTest, GivesBackThePlaneInsideAConfidentRim) {
  const Scene s;
  const MembraneFillParams params = test_params();
  ASSERT_EQ(params.cell, 2);
  const FloatImage out = membrane_fill_cpu(s.distance, s.confidence, params, 0.1, 100.0);
  double worst = 0, mean = 0;
  int filled = 0;
  for (int y = 0; y < kH; ++y) {
    for (int x = 0; x < kW; ++x) {
      if (!Scene::in_cap(y)) {
        ASSERT_EQ(out(x, y), s.distance(x, y)) << "pixel " << x << ", " << y << " was confident";
        continue;
      }
      const double error = std::abs(1.0 / out(x, y) - plane_inverse(x, y));
      worst = std::max(worst, error);
      mean += error;
      ++filled;
    }
  }
  mean /= filled;
  std::cout << filled << " pixels filled; inverse-distance error mean " << mean << ", largest "
            << worst << " (the wrong 3 m was off by up to 0.78)\n";
  // Exact but for the bilinear interpolation and the multigrid's last error: within 1e-4 but in the
  // top row, whose pixels lie beyond the first cells' centres (0.0007).
  EXPECT_LT(mean, 1e-4);
  EXPECT_LT(worst, 2e-3);
}

// The multigrid (the default) against the direct solve, on a rim that is no plane (a wavy room)
// around two regions: the cap at the top (whole rows: its rows are solved as cycles) and a region
// across the seam below the horizon, which the rows cut into runs.
TEST(MembraneFillTest, TheMultigridMatchesTheDirectSolve) {
  Scene s;
  for (int y = 0; y < kH; ++y) {
    for (int x = 0; x < kW; ++x) {
      const double phi = (x + 0.5) / kW * 2 * std::numbers::pi;
      const double wavy = 0.4 + 0.15 * std::sin(3 * phi) + 0.1 * std::cos(7.0 * y / kH);
      const bool seam = (x < 60 || x >= kW - 90) && y >= 150 && y < 230;
      if (Scene::in_blob(x, y)) continue;
      const bool plain = Scene::in_cap(y) || seam;
      s.distance(x, y) = plain ? 3.0f : float(1.0 / wavy);
      s.confidence(x, y) = plain ? 0.0f : 0.9f;
    }
  }
  MembraneFillParams direct = test_params();
  direct.solver = MembraneSolver::kDirect;
  const FloatImage a = membrane_fill_cpu(s.distance, s.confidence, test_params(), 0.1, 100.0);
  const FloatImage b = membrane_fill_cpu(s.distance, s.confidence, direct, 0.1, 100.0);
  double worst = 0, mean = 0;
  int filled = 0;
  for (int y = 0; y < kH; ++y) {
    for (int x = 0; x < kW; ++x) {
      if (s.confidence(x, y) > 0 || Scene::in_blob(x, y)) continue;
      ASSERT_NE(b(x, y), 3.0f) << "pixel " << x << ", " << y << " was not filled";
      const double difference = std::abs(1.0 / a(x, y) - 1.0 / b(x, y));
      worst = std::max(worst, difference);
      mean += difference;
      ++filled;
    }
  }
  mean /= filled;
  std::cout << filled << " pixels filled; multigrid - direct: mean " << mean << ", largest "
            << worst << " m^-1\n";
  EXPECT_LT(mean, 2e-4);
  EXPECT_LT(worst, 2e-3);
}

TEST(MembraneFillTest, SmallRegionsAreLeftAlone) {
  const Scene s;
  const FloatImage out = membrane_fill_cpu(s.distance, s.confidence, test_params(), 0.1, 100.0);
  for (int y = 100; y < 106; ++y) {
    for (int x = 300; x < 306; ++x) EXPECT_EQ(out(x, y), 3.0f) << "pixel " << x << ", " << y;
  }
}

TEST(MembraneFillTest, BadInputIsNamed) {
  const Scene s;
  EXPECT_EQ(omnisweep::testing::error_message<std::invalid_argument>([&] {
              membrane_fill_cpu(FloatImage(kW, kH - 2), s.confidence, test_params(), 0.1, 100);
            }),
            "membrane fill: the confidence is 512x256, the distance 512x254");
  EXPECT_EQ(omnisweep::testing::error_message<std::invalid_argument>([&] {
              membrane_fill_cpu(FloatImage(30, 15), FloatImage(30, 15), test_params(), 0.1, 100);
            }),
            "membrane fill: the panorama is 30x15; it must be 2:1 and a whole number of cells of "
            "2 pixels");
  MembraneFillParams bad = test_params();
  bad.cell = 0;
  EXPECT_EQ(omnisweep::testing::error_message<std::invalid_argument>(
                [&] { membrane_fill_cpu(s.distance, s.confidence, bad, 0.1, 100); }),
            "MembraneFillParams::cell is 0.000000; it must be in [1, 64]");
  EXPECT_THROW(membrane_fill_cpu(s.distance, s.confidence, test_params(), 1, 1),
               std::invalid_argument);
}

}  // namespace
}  // namespace omnisweep::stitch
