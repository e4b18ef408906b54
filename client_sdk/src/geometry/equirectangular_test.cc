#include "omnisweep/geometry/equirectangular.h"

#include <gtest/gtest.h>

namespace omnisweep {
namespace {

TEST(Equirectangular, ConventionOfAlgorithmMd) {
  const int w = 2048, h = 1024;
  // The centre column looks along +z, the left edge along -z, the top row up (-y).
  EXPECT_TRUE(equirect_direction<double>(w / 2.0 - 0.5, h / 2.0 - 0.5, w, h)
                  .isApprox(Eigen::Vector3d(0, 0, 1), 1e-12));
  EXPECT_LT(equirect_direction<double>(-0.5, h / 2.0 - 0.5, w, h).z(), -0.999999);
  EXPECT_LT(equirect_direction<double>(w / 2.0, 0, w, h).y(), -0.9999);
  // x grows towards +x at the centre.
  EXPECT_GT(equirect_direction<double>(w / 2.0 + 10, h / 2.0, w, h).x(), 0);
}

TEST(Equirectangular, PixelIsTheInverseOfDirection) {
  const int w = 640, h = 320;
  for (int y = 0; y < h; y += 7) {
    for (int x = 0; x < w; x += 5) {
      const Eigen::Vector2d back =
          equirect_pixel<double>(equirect_direction<double>(x, y, w, h), w, h);
      EXPECT_NEAR(back.x(), x, 1e-9);
      EXPECT_NEAR(back.y(), y, 1e-9);
    }
  }
}

}  // namespace
}  // namespace omnisweep
