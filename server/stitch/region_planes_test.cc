// The region planes: an unconfident ceiling pulled too far comes back onto the plane of its
// confident rim, a pixel halfway to the threshold gets half of it, a plane is never extrapolated
// beyond its support, confident and small regions are left alone, the result is reproducible, and
// bad input is named.
#include "server/stitch/region_planes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <stdexcept>

namespace omnisweep::stitch {
namespace {

constexpr int kW = 256, kH = 128;
constexpr double kMinDistance = 0.55, kMaxDistance = 100.0;

struct Hit {
  double v;        // inverse distance
  int plane;       // 0 ceiling, 1 floor, 2-5 walls
  double x, y, z;  // the point, metres
};

// A box room around the viewpoint: ceiling 1.5 m above, floor 1.2 m below, walls at x = -3, +3
// and y = -2.5, +2.5 (plane_fill.comp's frame: z up). Seen from inside, a ray's surface is the
// nearest plane it meets: the largest inverse distance among the planes.
Hit hit(int x, int y) {
  const double theta = 2.0 * std::numbers::pi * (x + 0.5) / kW;
  const double phi = std::numbers::pi * (y + 0.5) / kH;
  const double r[3] = {std::sin(phi) * std::cos(theta), std::sin(phi) * std::sin(theta),
                       std::cos(phi)};
  const double planes[6][3] = {{0, 0, 1 / 1.5}, {0, 0, -1 / 1.2}, {-1 / 3.0, 0, 0},
                               {1 / 3.0, 0, 0}, {0, -1 / 2.5, 0}, {0, 1 / 2.5, 0}};
  Hit h{-1, -1, 0, 0, 0};
  for (int k = 0; k < 6; ++k) {
    const double v = planes[k][0] * r[0] + planes[k][1] * r[1] + planes[k][2] * r[2];
    if (v > h.v) h = {v, k, r[0] / v, r[1] / v, r[2] / v};
  }
  return h;
}

struct Scene {
  FloatImage truth;  // inverse distance
  FloatImage distance;
  FloatImage confidence;
  std::vector<bool> low;
};

// Confident (0.6) and exact everywhere but where `low` holds: confidence 0.01 and the distance
// 25 % too far (the ISB filter's fill). `hole` pixels have no distance.
Scene make_scene(const std::function<bool(const Hit&, int, int)>& low,
                 const std::function<bool(const Hit&, int, int)>& hole = {}) {
  Scene s{FloatImage(kW, kH), FloatImage(kW, kH), FloatImage(kW, kH),
          std::vector<bool>(std::size_t(kW) * kH)};
  for (int y = 0; y < kH; ++y) {
    for (int x = 0; x < kW; ++x) {
      const std::size_t i = std::size_t(y) * kW + x;
      const Hit h = hit(x, y);
      s.truth.data()[i] = float(h.v);
      if (hole && hole(h, x, y)) {
        s.distance.data()[i] = 0.0f;
        s.confidence.data()[i] = 0.0f;
        continue;
      }
      s.low[i] = low(h, x, y);
      s.distance.data()[i] = float(1.0 / (s.low[i] ? 0.8 * h.v : h.v));
      s.confidence.data()[i] = s.low[i] ? 0.01f : 0.6f;
    }
  }
  return s;
}

// The ceiling more than 0.6 m from the walls: a plain region with a confident rim on its plane.
bool plain_ceiling(const Hit& h, int, int) {
  return h.plane == 0 && std::abs(h.x) < 2.4 && std::abs(h.y) < 1.9;
}

RegionPlaneParams params() { return RegionPlaneParams::for_width(kW); }

TEST(RegionPlanes, PlainCeilingReturnsToItsRimsPlane) {
  const Scene s = make_scene(plain_ceiling);
  const FloatImage out =
      region_planes_cpu(s.distance, s.confidence, params(), kMinDistance, kMaxDistance);
  int low = 0;
  double before = 0, after = 0;
  for (std::size_t i = 0; i < s.truth.size(); ++i) {
    if (!s.low[i]) {
      ASSERT_EQ(out.data()[i], s.distance.data()[i]) << "confident pixel " << i << " changed";
      continue;
    }
    ++low;
    before += std::abs(1.0 / s.distance.data()[i] - s.truth.data()[i]) / s.truth.data()[i];
    after += std::abs(1.0 / out.data()[i] - s.truth.data()[i]) / s.truth.data()[i];
  }
  ASSERT_GT(low, 2000);
  EXPECT_NEAR(before / low, 0.2, 1e-3);
  // alpha = 1 - 0.01 / 0.05 = 0.8 of the plane: what is left is 0.2 x the 20 % error.
  EXPECT_LT(after / low, 0.2 * 0.2 + 0.002);
}

TEST(RegionPlanes, HalfwayToTheThresholdGetsHalfThePlane) {
  Scene s = make_scene(plain_ceiling);
  // One ceiling pixel at half the threshold, still in the region.
  const std::size_t i = std::size_t(2) * kW + 40;
  ASSERT_TRUE(s.low[i]);
  s.confidence.data()[i] = 0.025f;
  const FloatImage out =
      region_planes_cpu(s.distance, s.confidence, params(), kMinDistance, kMaxDistance);
  const double own = 1.0 / s.distance.data()[i], truth = s.truth.data()[i];
  EXPECT_NEAR(1.0 / out.data()[i], 0.5 * own + 0.5 * truth, 1e-3 * truth);
}

TEST(RegionPlanes, APlaneIsNotExtrapolatedBeyondItsSupport) {
  // A plain patch of the wall x = +3 with confident wall on its left only: above, below and to
  // its right there is no distance. Its plane's inliers lie in two quadrants around every pixel
  // of it, so nothing is filled.
  auto patch = [](const Hit& h, int, int) {
    return h.plane == 3 && h.y > -1.0 && h.y < 1.0 && h.z > -0.5 && h.z < 0.5;
  };
  auto hole = [&](const Hit& h, int x, int y) {
    return h.plane == 3 && !patch(h, x, y) && (h.y >= 1.0 || h.z <= -0.5 || h.z >= 0.5);
  };
  RegionPlaneParams wide_rim = params();
  wide_rim.rim = 4;  // support enough for a plane on the one side (30 inliers)
  const Scene one_sided = make_scene(patch, hole);
  const FloatImage out = region_planes_cpu(one_sided.distance, one_sided.confidence, wide_rim,
                                           kMinDistance, kMaxDistance);
  int low = 0;
  for (std::size_t i = 0; i < out.size(); ++i) {
    ASSERT_EQ(out.data()[i], one_sided.distance.data()[i]) << "pixel " << i;
    low += one_sided.low[i];
  }
  ASSERT_GT(low, 200);
  // The same patch with confident wall all around is filled.
  const Scene surrounded = make_scene(patch);
  const FloatImage filled = region_planes_cpu(surrounded.distance, surrounded.confidence, wide_rim,
                                              kMinDistance, kMaxDistance);
  double after = 0;
  for (std::size_t i = 0; i < filled.size(); ++i)
    if (surrounded.low[i])
      after += std::abs(1.0 / filled.data()[i] - surrounded.truth.data()[i]) /
               surrounded.truth.data()[i];
  EXPECT_LT(after / low, 0.2 * 0.2 + 0.002);
}

TEST(RegionPlanes, SmallRegionsAndConfidentFramesAreLeftAlone) {
  // A patch of 5 x 5 pixels is below min_pixels (31 at this width).
  const Scene small =
      make_scene([](const Hit&, int x, int y) { return x >= 100 && x < 105 && y >= 60 && y < 65; });
  const FloatImage out =
      region_planes_cpu(small.distance, small.confidence, params(), kMinDistance, kMaxDistance);
  for (std::size_t i = 0; i < out.size(); ++i)
    ASSERT_EQ(out.data()[i], small.distance.data()[i]) << "pixel " << i;
  const Scene none = make_scene([](const Hit&, int, int) { return false; });
  const FloatImage same =
      region_planes_cpu(none.distance, none.confidence, params(), kMinDistance, kMaxDistance);
  EXPECT_TRUE(std::equal(same.data(), same.data() + same.size(), none.distance.data()));
}

TEST(RegionPlanes, Reproducible) {
  const Scene s = make_scene(plain_ceiling);
  const FloatImage a =
      region_planes_cpu(s.distance, s.confidence, params(), kMinDistance, kMaxDistance);
  const FloatImage b =
      region_planes_cpu(s.distance, s.confidence, params(), kMinDistance, kMaxDistance);
  EXPECT_TRUE(std::equal(a.data(), a.data() + a.size(), b.data()));
}

TEST(RegionPlanes, BadInputIsNamed) {
  const Scene s = make_scene(plain_ceiling);
  try {
    region_planes_cpu(s.distance, FloatImage(kW, kH / 2), params(), kMinDistance, kMaxDistance);
    FAIL() << "no error for a confidence of another size";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("256x64"), std::string::npos) << e.what();
  }
  RegionPlaneParams p = params();
  p.tau = 0;
  try {
    region_planes_cpu(s.distance, s.confidence, p, kMinDistance, kMaxDistance);
    FAIL() << "no error for tau 0";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("tau"), std::string::npos) << e.what();
  }
  p = params();
  p.max_planes = 33;
  EXPECT_THROW(region_planes_cpu(s.distance, s.confidence, p, kMinDistance, kMaxDistance),
               std::invalid_argument);
  EXPECT_THROW(region_planes_cpu(s.distance, s.confidence, params(), 2.0, 1.0),
               std::invalid_argument);
}

TEST(RegionPlanes, SettingsScaleWithTheWidth) {
  const RegionPlaneParams full = RegionPlaneParams::for_width(2048);
  EXPECT_EQ(full.rim, 8);
  EXPECT_EQ(full.min_pixels, 2000);
  EXPECT_EQ(full.cell, 8);
  const RegionPlaneParams quarter = RegionPlaneParams::for_width(512);
  EXPECT_EQ(quarter.rim, 2);
  EXPECT_EQ(quarter.min_pixels, 125);
  EXPECT_EQ(quarter.cell, 2);
}

}  // namespace
}  // namespace omnisweep::stitch
