// Parameters of distance estimation (ALGORITHM.md §3), with the reference implementation's
// defaults. check() throws std::invalid_argument naming the option that is wrong.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace omnisweep::depth {

// Reference cameras one frame can have (the kernels take their cameras as push constants).
inline constexpr std::size_t kMaxReferences = 8;
// How far the matching blur's taps reach at most, pixels (match_blur.comp's shared memory).
inline constexpr int kMatchBlurMaxRadius = 8;
// How far they reach for a Gaussian of `sigma` pixels at the matching resolution: 3 sigma.
inline int match_blur_radius(double sigma) { return int(std::ceil(3.0 * sigma)); }

// The matching cost of the sweep (ALGORITHM.md §3 step 3 is kAbsoluteDifference). The others
// compare matching features (shaders/matching_features.comp) that a camera's gain, colour cast
// and a smooth vignetting leave unchanged: colours normalised by the mean and deviation of their
// window, an 8-bit census of the luminance, or colours over their neighbourhood's mean (kRatio).
// docs/accuracy.md has what each does.
enum class MatchingCost { kAbsoluteDifference, kNormalised, kCensus, kNormalisedCensus, kRatio };
inline constexpr struct {
  MatchingCost cost;
  std::string_view name;
} kMatchingCostNames[] = {{MatchingCost::kAbsoluteDifference, "ad"},
                          {MatchingCost::kNormalised, "nad"},
                          {MatchingCost::kCensus, "census"},
                          {MatchingCost::kNormalisedCensus, "nad-census"},
                          {MatchingCost::kRatio, "ratio"}};
std::string_view name_of(MatchingCost cost);
std::optional<MatchingCost> matching_cost_named(std::string_view name);

struct DepthOptions {
  std::vector<int> references = {2, 3};  // cameras that get a distance map
  int num_candidates = 32;               // distances swept per pixel
  double min_distance = 0.55;            // d_min, metres
  double max_distance = 100.0;           // d_max, metres
  double sigma_i = 10.0;                 // range sigma of the ISB filter (8-bit guide units)
  double sigma_s = 25.0;  // spatial sigma for 1024 px; scaled with the matching width
  // Where the raw cost curves around a pixel are confident (their mean confidence, wta.glsl,
  // from 0.5 to 0.7), the spatial sigma falls from sigma_s to this (1024 px, scaled like it):
  // curves that already single out a distance need less of their neighbourhood
  // (docs/accuracy.md). 0: off, the paper's filter.
  double confident_sigma_s = 0;
  // A Gaussian blur of this sigma (pixels at 1024 px, scaled with the matching width) over the
  // matching images before the sweep, the guide and the matching features (match_blur.h;
  // docs/accuracy.md). 0: off, the paper's. Its taps reach 3 sigma, at most kMatchBlurMaxRadius
  // pixels at the matching resolution.
  double match_blur = 0;
  int matching_width = 1024;
  int matching_height = 1024;
  bool post_filter = true;  // step 6; off only to inspect the raw winner-takes-all
  // Store the cost volume as 16-bit floats where the device can (storageBuffer16BitAccess): half
  // the memory and traffic of the sweep and the filter, arithmetic still in 32 bits
  // (docs/performance.md has what it changes). false: 32-bit floats everywhere.
  bool half_costs = true;
  // At most this many references in one dispatch (0: all of them). Each holds a cost volume
  // while a frame runs, so fewer in a group lower the memory and raise the dispatches; groups
  // divide the references evenly, and also shrink by themselves where the device's buffer
  // limits need it.
  int max_group = 0;
  MatchingCost cost = MatchingCost::kAbsoluteDifference;
  // Estimate each camera's gain, colour cast and vignetting from the overlaps and undo them before
  // matching and stitching (photometric_model.h).
  bool correct_photometry = false;
  // Cameras each reference pixel is matched against: 1, the paper's (the camera with the longest
  // epipolar segment); 2, also the camera with the next longest, where it is at least
  // second_camera_power times as long, the two costs averaged (docs/accuracy.md).
  int match_cameras = 1;
  double second_camera_power = 0.5;
  // The features of the other costs, at 1024 px (scaled with the matching width).
  int feature_radius = 3;        // normalisation window: (2 r + 1)^2 pixels
  double feature_epsilon = 4.0;  // added to the window's deviation, 8-bit levels
  int census_radius = 2;         // distance of the census' eight neighbours, pixels
  double census_scale = 24.0;    // cost of one differing census bit
  int ratio_radius = 20;         // ratio: its mean's taps reach this far (Gaussian sigma r / 2)
  double ratio_epsilon = 1.0;    // ratio: added to the mean, 8-bit levels
  // The confidence's coarse agreement (docs/accuracy.md): each pixel's confidence times
  // exp(-(delta / t)^2), delta (m^-1) between its inverse distance and the winner of the filtered
  // curves summed over its 8 x 8 block. 0: off (the confidence of the cost curve alone).
  double coarse_agreement = 0.03;
  // The confidence's raw agreement (docs/accuracy.md): where the pixel's raw curve (the sweep's
  // costs, before the filter) has its lowest nearer than the filtered winner, its confidence
  // times exp(-(d p / t)^2), d where the filtered winner's raw cost lies in the raw curve's
  // range, p the raw curve's power (1 - lowest / highest), t this tolerance: low where the
  // filter carried a farther distance that the pixel's own curve disputes, so the stitcher's
  // fills replace it. The distances do not change. 0: off, the default: 0.2-0.3 take
  // blender-hall 37-48 % under the paper's MAE (the default 27 %) but lower how well the
  // confidence ranks the error, and the real kaist-rig frame's fills still turn its speckles into
  // near patches (docs/accuracy.md, stops 44-45).
  double raw_agreement = 0;

  void check(int num_cameras) const;
  // A radius given for 1024 px at the matching width (at least 1 pixel).
  int scaled_radius(int radius) const {
    return std::max(1, int(std::lround(radius * matching_width / 1024.0)));
  }
  // sigma_s at the matching resolution (ALGORITHM.md §3 step 4).
  double scaled_sigma_s() const { return sigma_s * matching_width / 1024.0; }
  double scaled_confident_sigma_s() const { return confident_sigma_s * matching_width / 1024.0; }
  double scaled_match_blur() const { return match_blur * matching_width / 1024.0; }
  // 1 / d of fractional candidate index k (k = 0: d_min, k = N - 1: d_max).
  double inverse_distance(double k) const {
    return 1.0 / min_distance +
           (1.0 / max_distance - 1.0 / min_distance) * k / (num_candidates - 1);
  }
};

// Named methods: each sets the variants (cost, photometric correction, cameras matched, confident
// sigma, the ISB filter's spatial sigma, and the stitcher's plane fill and region planes) at once;
// every other option keeps its value. "paper" is ALGORITHM.md, DepthOptions' and StitchOptions'
// defaults; "recommended" the matching variants alone; "accurate" the most accurate variant
// measured and the programs' default (docs/accuracy.md, "Defaults"): 27 % lower MAE than the
// paper's on blender-hall, 54 % on the synthetic frames, 11-19 % with sensor noise, and under
// lenses with different gains and vignetting within 1.11-1.19 x of its MAE without them (with
// noise).
struct Method {
  std::string_view name;
  MatchingCost cost;
  bool correct_photometry;
  int match_cameras;
  double confident_sigma_s;
  double sigma_s;      // DepthOptions::sigma_s
  double plane_fill;   // StitchOptions::plane_fill
  bool region_planes;  // StitchOptions::region_planes
};
inline constexpr Method kMethods[] = {
    {"paper", MatchingCost::kAbsoluteDifference, false, 1, 0.0, 25.0, 0.0, false},
    {"recommended", MatchingCost::kAbsoluteDifference, true, 2, 5.0, 25.0, 0.0, false},
    {"accurate", MatchingCost::kAbsoluteDifference, true, 2, 5.0, 20.0, 0.05, true}};
// The programs' method when none is named (omnisweep-process, -server, -depth, -bench's model).
inline constexpr std::string_view kDefaultMethod = "accurate";
// The named method; nullptr where none has that name.
const Method* method_named(std::string_view name);
// Sets `options`' matching variants and sigma_s to the named method's; false (and `options`
// unchanged) where no method has that name.
bool apply_method(std::string_view name, DepthOptions& options);
// The flags that a method stands for beyond the paper's, e.g. "--correct-photometry
// --match-cameras 2" ("" for the paper's).
std::string method_flags(const Method& method);

}  // namespace omnisweep::depth
