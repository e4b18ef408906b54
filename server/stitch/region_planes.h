// Region planes (StitchOptions::region_planes, --region-planes; docs/accuracy.md, "Region
// planes"): the plane fill (plane_fill.h) fits one plane per window of +-17 degrees, and a plain
// ceiling or wall has no confident support that near most of its pixels; the ISB filter then
// fills it from whatever its reach takes in (blender-hall's ceiling: 18 % too far). Here each
// connected region of unconfident pixels is taken whole: the confident pixels on its rim and in
// its holes (a ceiling's creases with the walls, the edges of its lights) are its support; planes
// are found among them by sequential RANSAC; and each unconfident pixel takes, among the planes
// whose inliers within 60 degrees surround it (in at least three of the four quadrants around its
// ray, so that a plane is interpolated, never extrapolated: a wall's plane does not run on into
// the ceiling above it), the one nearest its own inverse distance.
//
// The work is done on blocks of `block` x `block` pixels (4 at 2048 x 1024), so that the
// labelling and the search for support touch a sixteenth of the panorama:
//   1. blocks: a block's unconfident pixels (a distance, confidence < fill_below) are counted,
//      and its most confident pixel of at least `support` (the first of equals) is its support
//      pixel;
//   2. regions: the 8-connected components (wrapping left to right) of blocks with an unconfident
//      pixel, those with at least min_pixels unconfident pixels, numbered in the order of their
//      first block, at most max_regions;
//   3. support: a block's support pixel supports every region (its first 8) with a block within
//      `rim` blocks (a disk); of a region's supports, a sample of at most kRegionPlaneSample is
//      kept, picked by a hash of (block, region): those of the lowest 8-bit hash bins that hold
//      at most kRegionPlaneCandidates together, in hash order;
//   4. planes: sequential RANSAC over the sample (`draws` hypotheses through three supports
//      drawn by a hash of (region, plane, draw), each scored by MSAC on the supports left; the
//      best (the first of equals) refitted three times by least squares on its inliers,
//      |a . r - v| < tau v; its inliers removed; while a plane has at least max(3, the sample's
//      share of min_inliers, the sample / min_inlier_fraction) inliers);
//   5. surround: per block of a region, the planes whose inliers within surround_angle_deg of
//      its centre ray lie in >= 3 of the 4 quadrants of the tangent plane at that ray;
//   6. each unconfident pixel of such a block takes the surrounding plane nearest its own inverse
//      distance, mixed with it by alpha = 1 - confidence / fill_below (as the plane fill) and
//      clamped to the sweep's range.
//
// It runs on the GPU (RegionPlanes, the region_*.comp kernels); region_planes_cpu is the plain
// C++ reference, in float arithmetic where a decision depends on it. Keep the two in step.
#pragma once

#include "omnisweep/gpu/buffer.h"
#include "omnisweep/gpu/kernel.h"
#include "omnisweep/gpu/sequence.h"
#include "omnisweep/image/image.h"

namespace omnisweep::stitch {

// Fixed by the kernels' shared memory (region_ransac_step.comp, region_sample.comp).
constexpr int kRegionPlaneSample = 1024;      // supports per region, at most
constexpr int kRegionPlaneCandidates = 2048;  // candidates the sample is sorted from, at most
constexpr int kRegionPlaneMaxRegions = 16;
constexpr int kRegionPlaneMaxPlanes = 16;  // per region (4 surround bits each in 64 bits)

// The settings at a 2048 x 1024 panorama (block and min_pixels scale with the width).
struct RegionPlaneParams {
  double fill_below = 0.05;  // unconfident: confidence below this (the regions)
  double support = 0.3;      // support pixels: of at least this confidence
  int block = 4;             // pixels per side of a block
  int rim = 2;               // blocks: how far from a region its support may lie
  int min_pixels = 2000;     // regions with fewer unconfident pixels are left alone
  int max_regions = 16;      // at most kRegionPlaneMaxRegions
  int max_planes = 12;       // per region, at most kRegionPlaneMaxPlanes
  int draws = 1024;          // RANSAC hypotheses per plane
  double tau = 0.06;         // an inlier's inverse distance is within tau x its own of the plane
  int min_inliers = 30;      // a plane needs this many support pixels' worth of inliers
  int min_inlier_fraction = 50;  // and 1 / this of the sample
  // A plane surrounds a block through its inliers within this angle of the block's centre ray
  // (90: the whole hemisphere, as before stop 42). Far inliers let a plane found by chance
  // through a few scattered supports surround a whole plain ceiling (docs/accuracy.md).
  double surround_angle_deg = 60.0;
  // For a panorama `width` pixels wide: block and min_pixels scaled from 2048 (the rim, in
  // blocks, stays 8 pixels' worth).
  static RegionPlaneParams for_width(int width);
  // Throws std::invalid_argument naming a setting out of range.
  void check() const;
};

// `distance` (metres, 0 = none) with its unconfident regions replaced as above. Pixels outside
// such regions, and those no plane surrounds, are copied. Deterministic. Throws
// std::invalid_argument when the images differ in size or a setting is out of range.
FloatImage region_planes_cpu(const FloatImage& distance, const FloatImage& confidence,
                             const RegionPlaneParams& params, double min_distance,
                             double max_distance);

// The same on the GPU, for panoramas of width x height.
class RegionPlanes {
 public:
  RegionPlanes(gpu::Context& context, int width, int height, const RegionPlaneParams& params,
               double min_distance, double max_distance);

  // Records the region planes into `seq` after what writes `distance` (float metres) and
  // `confidence`; `distance` is rewritten in place.
  void record(gpu::Sequence& seq, gpu::Buffer& distance, const gpu::Buffer& confidence) const;

 private:
  int width_, height_;
  RegionPlaneParams params_;
  double min_distance_, max_distance_;
  int blocks_x_, blocks_y_;
  gpu::Buffer table_;       // the rays (plane_fill.h's table)
  gpu::Buffer blocks_;      // per block: unconfident count, support pixel
  gpu::Buffer parent_;      // per block: union-find parent, then the root
  gpu::Buffer sizes_;       // per block (as root): unconfident pixels of its component
  gpu::Buffer slots_;       // per block (as root): its region, if it is one
  gpu::Buffer regions_;     // the regions' records (region_planes.glsl)
  gpu::Buffer histogram_;   // per region, 256 bins of the supports' hashes
  gpu::Buffer candidates_;  // per region, kRegionPlaneCandidates (hash, block)
  gpu::Buffer sample_;      // per region, kRegionPlaneSample (ray, v)
  gpu::Buffer alive_;       // per region, the sample's supports not yet an inlier (two lists)
  gpu::Buffer tags_;        // per region and support, the plane it is an inlier of
  gpu::Buffer scores_;      // per region and draw, (a, score) (two planes')
  gpu::Buffer planes_;      // per region, kRegionPlaneMaxPlanes planes
  gpu::Buffer surround_;    // per block: the planes that surround it (bits), its region
  gpu::Kernel blocks_kernel_, merge_, flatten_, number_, support_, threshold_, sample_kernel_,
      step_, surround_kernel_, apply_;
};

}  // namespace omnisweep::stitch
