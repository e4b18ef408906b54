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

#include "server/stitch/region_planes_scene.h"

namespace omnisweep::stitch {
namespace {

using namespace region_test;  // NOLINT(google-build-using-namespace): the scene

RegionPlaneParams params() { return RegionPlaneParams::for_width(kW); }

TEST(RegionPlanes, PlainCeilingReturnsToItsRimsPlane) {
  const Scene s = make_scene(plain_ceiling);
  const FloatImage out =
      region_planes_cpu(s.distance, s.confidence, params(), kMinDistance, kMaxDistance);
  int low = 0, kept = 0;
  double before = 0, after = 0;
  for (std::size_t i = 0; i < s.truth.size(); ++i) {
    if (!s.low[i]) {
      ASSERT_EQ(out.data()[i], s.distance.data()[i]) << "confident pixel " << i << " changed";
      continue;
    }
    ++low;
    before += std::abs(1.0 / s.distance.data()[i] - s.truth.data()[i]) / s.truth.data()[i];
    if (out.data()[i] == s.distance.data()[i]) {
      ++kept;
      continue;
    }
    after += std::abs(1.0 / out.data()[i] - s.truth.data()[i]) / s.truth.data()[i];
  }
  ASSERT_GT(low, 2000);
  EXPECT_NEAR(before / low, 0.2, 1e-3);
  // The ceiling's corners, whose far rim lies beyond the surround's 60 degrees, may keep theirs.
  EXPECT_LT(kept, low / 50);
  // alpha = 1 - 0.01 / 0.05 = 0.8 of the plane: what is left is 0.2 x the 20 % error.
  EXPECT_LT(after / (low - kept), 0.2 * 0.2 + 0.002);
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

TEST(RegionPlanes, OnlyInliersWithinTheSurroundAngleCount) {
  // The zenith of the plain ceiling: its rim lies 52-64 degrees away. Within 60 degrees its
  // inliers surround it; within 30 none count, so it keeps its own distance.
  const Scene s = make_scene(plain_ceiling);
  const std::size_t zenith = 10;  // row 0
  ASSERT_TRUE(s.low[zenith]);
  const double truth = s.truth.data()[zenith];
  const FloatImage wide =
      region_planes_cpu(s.distance, s.confidence, params(), kMinDistance, kMaxDistance);
  EXPECT_NEAR(1.0 / wide.data()[zenith], 0.8 * truth + 0.2 / s.distance.data()[zenith],
              1e-3 * truth);
  RegionPlaneParams narrow = params();
  narrow.surround_angle_deg = 30;
  const FloatImage kept =
      region_planes_cpu(s.distance, s.confidence, narrow, kMinDistance, kMaxDistance);
  EXPECT_EQ(kept.data()[zenith], s.distance.data()[zenith]);
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
  p.surround_angle_deg = 120;
  EXPECT_THROW(region_planes_cpu(s.distance, s.confidence, p, kMinDistance, kMaxDistance),
               std::invalid_argument);
  p = params();
  p.max_planes = kRegionPlaneMaxPlanes + 1;
  EXPECT_THROW(region_planes_cpu(s.distance, s.confidence, p, kMinDistance, kMaxDistance),
               std::invalid_argument);
  EXPECT_THROW(region_planes_cpu(s.distance, s.confidence, params(), 2.0, 1.0),
               std::invalid_argument);
}

TEST(RegionPlanes, SettingsScaleWithTheWidth) {
  const RegionPlaneParams full = RegionPlaneParams::for_width(2048);
  EXPECT_EQ(full.block, 4);
  EXPECT_EQ(full.rim, 2);
  EXPECT_EQ(full.min_pixels, 2000);
  const RegionPlaneParams quarter = RegionPlaneParams::for_width(512);
  EXPECT_EQ(quarter.block, 1);
  EXPECT_EQ(quarter.rim, 2);
  EXPECT_EQ(quarter.min_pixels, 125);
}

}  // namespace
}  // namespace omnisweep::stitch
