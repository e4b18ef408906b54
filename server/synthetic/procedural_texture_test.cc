#include "server/synthetic/procedural_texture.h"

#include <gtest/gtest.h>

#include <cmath>

namespace omnisweep::synthetic {
namespace {

TEST(ProceduralTexture, ValueNoiseIsBoundedContinuousAndDeterministic) {
  for (int i = 0; i < 1000; ++i) {
    const Eigen::Vector3f p(0.37f * i, -0.11f * i, 0.05f * i + 3);
    const float n = value_noise(p, 9);
    EXPECT_GE(n, 0.0f);
    EXPECT_LE(n, 1.0f);
    EXPECT_EQ(n, value_noise(p, 9));
    EXPECT_NEAR(value_noise(p + Eigen::Vector3f(1e-4f, 0, 0), 9), n, 1e-3f);
  }
}

TEST(ProceduralTexture, DetailFinerThanTheFootprintFadesToItsMean) {
  // Spread of fbm values over many points: large for a fine footprint, near zero when every
  // octave is below two footprints (so a coarse pixel sees the mean, not aliasing).
  auto spread = [](float footprint) {
    float lo = 1, hi = 0;
    for (int i = 0; i < 2000; ++i) {
      const float v =
          filtered_fbm(Eigen::Vector3f(0.713f * i, 0.291f * i, -0.5f * i), 0.5f, footprint, 3);
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
    return hi - lo;
  };
  EXPECT_GT(spread(0.001f), 0.3f);
  EXPECT_LT(spread(0.3f), spread(0.05f));
  EXPECT_LT(spread(1.0f), 1e-6f);
}

TEST(ProceduralTexture, PlainMaterialIsUniform) {
  Material m;
  m.color_a = {0.2f, 0.4f, 0.6f};
  EXPECT_EQ(albedo(m, {1, 2, 3}, {0, 0, 1}, 0.01f), m.color_a);
  m.pattern = Pattern::kTiles;
  m.scale = 0.5f;
  const Eigen::Vector3f a = albedo(m, {0.01f, 2, 0.25f}, {0, -1, 0}, 0.001f);  // on a mortar line
  const Eigen::Vector3f b = albedo(m, {0.25f, 2, 0.25f}, {0, -1, 0}, 0.001f);  // mid-tile
  EXPECT_LT(a.sum(), b.sum());
}

}  // namespace
}  // namespace omnisweep::synthetic
