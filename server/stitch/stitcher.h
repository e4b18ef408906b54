// Distance-aware stitching (paper §3.3, ALGORITHM.md §5): two (or more) reference fisheye
// distance maps and their colour images become an equirectangular colour + distance panorama
// seen from the viewpoint (by default the mean position of the references). The forward warp with
// z-buffer and directional inpainting of the shared reprojection module (every reference in
// each dispatch: one layer each), then one merge kernel with blending weights computed on the
// GPU once per calibration.
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "omnisweep/reproject/forward_warp.h"
#include "omnisweep/rig/rig.h"
#include "server/stitch/edge_check.h"
#include "server/stitch/membrane_fill.h"
#include "server/stitch/plane_fill.h"
#include "server/stitch/region_planes.h"
#include "server/stitch/temporal_filter.h"

namespace omnisweep::stitch {

struct StitchOptions {
  int panorama_width = 2048;
  int panorama_height = 1024;
  std::optional<Eigen::Vector3d> viewpoint{};  // rig frame; default: mean of the references
  double min_distance = 0.55;
  double max_distance = 100.0;
  int inpaint_passes = 32;
  // The confidence's scale of inverse-distance disagreement (1/m): between a warped point and
  // what its reference saw, and between references (stitch_merge.comp). About two candidate
  // spacings of the default sweep.
  double confidence_tolerance = 0.1;
  // The plane fill (plane_fill.h): the confidence below which the merged inverse distance is
  // replaced by a plane fitted to the confident pixels around it, in [0, 1); 0: off (the
  // default, ALGORITHM.md). Needs the cost confidences (stitch()'s `confidence`); without them
  // nothing is filled.
  double plane_fill = 0.0;
  // The region planes (region_planes.h): each unconfident region's distances from the planes
  // RANSAC finds on its confident rim, where they surround the pixel; after the plane fill. Off
  // by default (ALGORITHM.md). Needs the cost confidences, as the plane fill.
  bool region_planes = false;
  // The edge check (edge_check.h): the confidence near a depth step without a colour step, a
  // distance the filter carried across a plain surface, times 0.1; after the fills. Off by
  // default (ALGORITHM.md). Needs the cost confidences, as the plane fill.
  bool edge_check = false;
  // The membrane fill (membrane_fill.h): each large unconfident region's inverse distance solved
  // from the confident distances around it; after the edge check, before the temporal filter. Off
  // by default (ALGORITHM.md). Needs the cost confidences, as the plane fill, and a panorama whose
  // sides are whole numbers of its cells.
  bool membrane_fill = false;
  // A temporal filter on the panorama's distance (temporal_filter.h) for streams: each frame
  // then depends on the ones before it. None by default.
  std::optional<TemporalOptions> temporal{};
  // Throws std::invalid_argument naming the field, its value and what is allowed.
  void check() const;
};

struct Panorama {
  Rgb8Image rgb;
  FloatImage distance;  // metres from the viewpoint; 0 where no reference saw anything
  // Per pixel in [0, 1]: how far to trust `distance` (stitch_merge.comp; 0 where no value).
  FloatImage confidence;
  std::vector<std::pair<std::string, double>> stage_ms;
};

class Stitcher {
 public:
  // `matching_rig`: the calibration at the resolution of the distance maps; `color_rig`: at
  // the resolution of the colour images (may be higher); `usable` per camera at the matching
  // resolution (or empty).
  Stitcher(gpu::Context& context, const Rig& matching_rig, const Rig& color_rig,
           const std::vector<int>& references, const std::vector<std::optional<Gray8Image>>& usable,
           const StitchOptions& options);

  // distance: per reference, matching resolution (metres); colour: per reference, colour
  // resolution; confidence: per reference, the cost confidences at the matching resolution
  // (DepthResult::confidence), or empty (the panorama's confidence then comes from the
  // geometry alone).
  Panorama stitch(std::span<const FloatView> distance, std::span<const Rgb8View> color,
                  std::span<const FloatView> confidence = {});

  // The same on distance maps already on the GPU (DepthEstimator::distance_buffer: reference k's
  // map at float k x width x height), in a submission the caller owns: upload_color, record
  // into `seq` after what writes `distance`, submit, then download. With the depth estimator
  // recorded first, a frame is one submission from the camera images to the panorama: no host
  // round trip between them. `distance` (and `confidence`, laid out the same way, or null) must
  // stay alive until the submission has run.
  void upload_color(std::span<const Rgb8View> color);
  // The uploaded colour images, packed RGBA8, reference after reference (cameras references()
  // of color_rig()): a caller may change them in place in `seq` before record().
  gpu::Buffer& color_buffer() { return color_; }
  const Rig& color_rig() const { return color_rig_; }
  const std::vector<int>& references() const { return references_; }
  void record(gpu::Sequence& seq, const gpu::Buffer& distance,
              const gpu::Buffer* confidence = nullptr);
  Panorama download() const;

  const Eigen::Vector3d& viewpoint() const { return viewpoint_; }
  // With StitchOptions::temporal: the next frame starts the filter again (a new scene or source).
  void reset_temporal() {
    if (temporal_) temporal_->reset();
  }
  // The blending weights per reference (panorama size), as computed on the GPU.
  std::vector<FloatImage> weights() const;
  std::uint64_t gpu_bytes() const { return gpu_bytes_; }

 private:
  void compute_weights(const std::vector<std::optional<Gray8Image>>& usable);
  void check_color(std::span<const Rgb8View> color) const;

  gpu::Context* context_;
  StitchOptions options_;
  std::vector<int> references_;
  Rig matching_rig_;
  Rig color_rig_;
  Eigen::Vector3d viewpoint_;
  std::uint64_t allocated_before_;
  std::optional<reproject::ForwardWarper> warper_;  // one layer per reference
  gpu::Buffer distances_;    // stitch()'s input maps, reference after reference
  gpu::Buffer confidences_;  // and their confidences
  gpu::Buffer cameras_;
  gpu::Buffer weights_;
  gpu::Buffer color_;
  gpu::Buffer out_color_;
  gpu::Buffer out_distance_;
  gpu::Buffer out_confidence_;
  gpu::Kernel merge_;
  std::optional<PlaneFill> plane_fill_;
  std::optional<gpu::Buffer> merged_distance_;  // the merge's distances, with the plane fill
  std::optional<RegionPlanes> region_planes_;
  std::optional<EdgeCheck> edge_check_;
  std::optional<MembraneFill> membrane_fill_;
  std::optional<TemporalFilter> temporal_;
  gpu::Sequence sequence_;
  std::uint64_t gpu_bytes_ = 0;
};

}  // namespace omnisweep::stitch
