// Region planes (--region-planes; docs/accuracy.md, "Region planes"): the plane fill
// (plane_fill.h) fits one plane per window of +-17 degrees, and a plain ceiling or wall has no
// confident support that near most of its pixels; the ISB filter then fills it from whatever its
// reach takes in (blender-hall's ceiling: 18 % too far). Here each connected region of
// unconfident pixels is taken whole: the confident pixels on its rim and in its holes (a
// ceiling's creases with the walls, the edges of its lights) are its support; planes are found
// among them by sequential RANSAC; and each unconfident pixel takes, among the planes whose
// inliers surround it (in at least three of the four quadrants around its ray, so that a plane
// is interpolated, never extrapolated: a wall's plane does not run on into the ceiling above
// it), the one nearest its own inverse distance.
//
// It runs on the host, on the downloaded panorama (omnisweep-process and the accuracy bench);
// the server does not run it yet. It is written for a GPU port: fixed-size loops, hypotheses
// drawn from a hash of (region, plane, draw) rather than a stateful generator.
#pragma once

#include "omnisweep/image/image.h"

namespace omnisweep::stitch {

// The settings at a 2048 x 1024 panorama (the pixel sizes scale with the width).
struct RegionPlaneParams {
  double fill_below = 0.05;  // unconfident: confidence below this (the regions)
  double support = 0.3;      // the rim's pixels of at least this confidence are the support
  int rim = 8;               // pixels: how far outside a region its support may lie
  int min_pixels = 2000;     // smaller regions are left alone
  int max_planes = 12;       // per region, at most 32
  int draws = 2000;          // RANSAC hypotheses per plane
  int max_scored = 4096;     // supports a hypothesis is scored on (evenly strided)
  double tau = 0.06;         // an inlier's inverse distance is within tau x its own of the plane
  int min_inlier_fraction = 50;  // a plane needs 30 inliers and 1 / this of the region's support
  int cell = 8;                  // pixels per side of the cells the surround test is made on
  int surround_samples = 400;    // inliers per plane the surround test looks at (strided)
  // For a panorama `width` pixels wide: rim, min_pixels and cell scaled from 2048.
  static RegionPlaneParams for_width(int width);
};

// `distance` (metres, 0 = none) with its unconfident regions replaced as above, each pixel
// mixed with its own inverse distance by alpha = 1 - confidence / fill_below (as the plane
// fill) and clamped to the sweep's range [1 / max_distance, 1 / min_distance]. Pixels outside
// such regions, and those no plane surrounds, are copied. Deterministic. Throws
// std::invalid_argument when the images differ in size or a setting is out of range.
FloatImage region_planes_cpu(const FloatImage& distance, const FloatImage& confidence,
                             const RegionPlaneParams& params, double min_distance,
                             double max_distance);

}  // namespace omnisweep::stitch
