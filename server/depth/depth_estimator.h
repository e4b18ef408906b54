// Distance estimation on the GPU (paper §3.1-3.2, ALGORITHM.md §3): camera selection once per
// calibration, then per frame: YCbCr guides, sphere sweep + L1 cost, the ISB filter over every
// candidate, winner-takes-all with the parabola step (in the filter's last pass), and the
// distance post-filter. Every dispatch covers all reference cameras at once (z = the reference's
// slot), so a frame is the same few dozen dispatches whatever the number of references; where
// the volumes of all references do not fit the device's buffer limits, the references are taken
// in groups that share one volume (group_size()).
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "omnisweep/gpu/kernel.h"
#include "omnisweep/gpu/sequence.h"
#include "omnisweep/image/image.h"
#include "omnisweep/rig/rig.h"
#include "server/depth/cost_volume.h"
#include "server/depth/depth_options.h"
#include "server/depth/isb_filter.h"
#include "server/depth/match_blur.h"

namespace omnisweep::depth {

struct DepthResult {
  std::vector<FloatImage> distance;  // per reference, metres, matching resolution
  // Per reference, matching resolution: the confidence of each distance's cost curve in [0, 1]
  // (the peak ratio, wta.glsl): near 0 where the curve is flat or has two equal minima.
  std::vector<FloatImage> confidence;
  std::vector<std::pair<std::string, double>> stage_ms;  // GPU time per stage (both references)
};

class DepthEstimator {
 public:
  // `rig` is the calibration at the matching resolution (Rig::resized); `usable` holds, per
  // camera, a mask at that resolution (non-zero = usable, ALGORITHM.md §2) or nullopt (all usable).
  // Throws std::invalid_argument for bad options, GpuError when the device cannot do it.
  DepthEstimator(gpu::Context& context, const Rig& rig,
                 const std::vector<std::optional<Gray8Image>>& usable, const DepthOptions& options);

  // Images: one RGB image per camera at the matching resolution.
  DepthResult estimate(std::span<const Rgb8View> images);

  // The same without leaving the GPU, for a caller that records what follows into the same
  // submission (the stitcher): upload the images, record depth into `seq` (between its begin()
  // and submit), and the distance maps (matching width x height floats, metres) are in
  // distance_buffer() once `seq` has run, reference slot k's at float k x width x height, and
  // their confidences likewise in confidence_buffer().
  void upload(std::span<const Rgb8View> images) { upload_images(images); }
  // The uploaded images, packed RGBA8, camera after camera: a caller may change them in place
  // (GpuPhotometricCorrection) in `seq` before record().
  gpu::Buffer& image_buffer() { return images_; }
  const Rig& rig() const { return rig_; }
  void record(gpu::Sequence& seq);
  const gpu::Buffer& distance_buffer() const;
  const gpu::Buffer& confidence_buffer() const { return confidences_; }

  // Stage by stage, for tests and benchmarks: the camera selection map of reference slot `slot`
  // (-1 = none), and the cost volume of the last uploaded images, raw or ISB-filtered, as
  // out[p * N + i].
  Image<std::int32_t> selection(int slot) const;
  // The second camera of each pixel (DepthOptions::match_cameras = 2; -1 = none).
  Image<std::int32_t> second_selection(int slot) const;
  std::vector<float> cost_volume(std::span<const Rgb8View> images, int slot, bool filtered);
  // The ISB filter's level 1 as the last group of the last estimate() left it (filtered costs of
  // that group's slot `slot_in_group`, out[p * N + i]), and its size.
  std::vector<float> filter_level_costs(int slot_in_group, int* width, int* height) const;
  // With a robust cost: camera `camera`'s matching features, as the last cost_volume() or
  // estimate() computed them (width x height, packed as matching_features_cpu packs them).
  std::vector<std::uint32_t> matching_features(int camera) const;

  const DepthOptions& options() const { return options_; }
  const VolumeLayout& volume_layout() const { return volume_.layout(); }
  // References whose volumes one dispatch holds (every reference, unless they do not fit).
  int group_size() const { return volume_.layout().slots; }
  // Device memory held by this estimator, bytes.
  std::uint64_t gpu_bytes() const;

 private:
  void upload_images(std::span<const Rgb8View> images);
  // Sweep and filter of the group of references from slot `first` (group_size() of them, fewer
  // at the end); `finish` ends in the distance maps, otherwise the volume is left behind.
  void record_group(gpu::Sequence& seq, int first, bool filter, bool finish);
  void record_guides(gpu::Sequence& seq);    // no barrier: the caller puts one before a use
  void record_features(gpu::Sequence& seq);  // the same
  // Whether the sweep compares matching features rather than the images themselves.
  bool robust_cost() const { return options_.cost != MatchingCost::kAbsoluteDifference; }
  bool ratio_cost() const { return options_.cost == MatchingCost::kRatio; }
  // After the filters of every group (the guides as they left them).
  void record_post_filter(gpu::Sequence& seq);
  // The coarse agreement: after group `first`'s fused filter its blocks' winners (apply false);
  // once the distances are final, every slot's confidences times it (apply true, first 0).
  void record_coarse_agreement(gpu::Sequence& seq, int first, bool apply);
  // Whether a full frame's filter ends in winner-takes-all (a last upsample to fuse it into),
  // which leaves the full-resolution guides as the images gave them.
  bool winner_in_filter() const { return filter_.levels() >= 2; }
  bool confident_sigma() const { return options_.confident_sigma_s > 0; }
  // The images the sweep, the guides and the features read: blurred where match_blur asks.
  const gpu::Buffer& matched_images() const { return blur_ ? blurred_ : images_; }
  // The blur of images_ into blurred_ (stage "match_blur") and a barrier, where match_blur asks
  // (else nothing).
  void record_blur(gpu::Sequence& seq);
  std::uint32_t slots() const { return std::uint32_t(options_.references.size()); }

  std::uint64_t allocated_before_;  // device memory in use before this estimator
  DepthOptions options_;
  Rig rig_;
  int width_;
  int height_;
  VolumeLayout layout_;
  gpu::Kernel selection_kernel_;
  gpu::Kernel guide_kernel_;
  gpu::Kernel features_kernel_;
  gpu::Kernel sweep_kernel_;
  gpu::Kernel wta_kernel_;
  gpu::Kernel agreement_kernel_;   // the confidence's coarse agreement (coarse_agreement.comp)
  CostVolume volume_;              // the full-resolution cost volumes of one group of references
  IsbFilter filter_;               // their pyramid
  IsbFilter post_filter_;          // one channel, every reference, for the distance maps
  gpu::Buffer images_;             // RGBA8 per camera
  std::optional<MatchBlur> blur_;  // DepthOptions::match_blur > 0
  gpu::Buffer blurred_;            // images_ blurred (match_blur only)
  gpu::Buffer features_;           // RGBA8 per camera: matching features (robust costs only)
  gpu::Buffer masks_;              // usable masks, a byte per pixel (the ratio cost only)
  gpu::Buffer guide_;              // per reference slot
  gpu::Buffer dummy_;
  gpu::Buffer cameras_;           // per reference slot, every camera (reproject::pack_cameras)
  gpu::Buffer selections_;        // per reference slot
  CostVolume distances_;          // one channel, every reference slot
  gpu::Buffer confidences_;       // a float plane per reference slot
  gpu::Buffer agreement_blocks_;  // the coarse agreement's block winners (coarse_agreement.comp)
  gpu::Sequence sequence_;
  std::uint64_t gpu_bytes_ = 0;  // held after construction
};

}  // namespace omnisweep::depth
