// Plain C++ versions of every depth kernel (ALGORITHM.md §3-4), written for clarity, not speed:
// the tests compare the shaders against them, and the benchmark uses winner_take_all_cpu on
// volumes filtered by other methods.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "omnisweep/image/image.h"
#include "omnisweep/rig/rig.h"
#include "server/depth/depth_options.h"

namespace omnisweep::depth {

struct SelectionReference {
  Image<std::int32_t> selected;  // -1 = none
  // The camera with the next longest segment, where it is at least second_power times the
  // longest (DepthOptions::match_cameras = 2); -1 = none.
  Image<std::int32_t> second;
  // 1 where the decision is within rounding of a tie or a boundary (two cameras within 1e-3 px
  // of displacement, displacement within 1e-3 px of the 1 px threshold or of second_power times
  // the longest, a projection within
  // 2e-4 px of a pixel-rounding boundary, a ray within 1e-4 rad of a lens' valid cone); float
  // and double may then legitimately differ.
  Gray8Image fragile;
};

// ALGORITHM.md §3 step 2 in double precision; `usable` as for DepthEstimator.
SelectionReference select_cameras_cpu(const Rig& rig, int reference,
                                      const std::vector<std::optional<Gray8Image>>& usable,
                                      double d_min, double d_max, double second_power = 0.5);

// The N matching costs of reference pixel (x, y) (ALGORITHM.md §3 step 3).
std::vector<float> sweep_cost_cpu(const Rig& rig, int reference, int selected,
                                  std::span<const Rgb8View> images, const DepthOptions& options,
                                  int x, int y);

// The matching features of an image (shaders/matching_features.comp, packed as it packs them):
// window-normalised colour in the low three bytes, the luminance census in the high byte.
// `radius` and `census_radius` in pixels of this image.
std::vector<std::uint32_t> matching_features_cpu(const Rgb8Image& rgb, int radius,
                                                 int census_radius, double epsilon);

// The ratio cost's features (MatchingCost::kRatio, the shader's ratio mode): each channel over
// the Gaussian mean of its usable neighbours (9 x 9 taps k radius / 4 from it, k in [-4, 4], sigma
// radius / 2; `usable` none: every pixel), 128 I / (mean + epsilon); the census as above.
std::vector<std::uint32_t> ratio_features_cpu(const Rgb8Image& rgb, const Gray8Image* usable,
                                              int radius, int census_radius, double epsilon);

// The N costs of reference pixel (x, y) under options.cost (other than the paper's), on every
// camera's matching features (width x height each, as matching_features_cpu gives them).
std::vector<float> feature_cost_cpu(const Rig& rig, int reference, int selected,
                                    const std::vector<std::vector<std::uint32_t>>& features,
                                    const DepthOptions& options, int x, int y);

// BT.709 studio-range YCbCr of an RGB image, packed as the shaders' guide (y | cb << 8 | cr << 16).
std::vector<std::uint32_t> ycbcr_guide_cpu(const Rgb8Image& rgb);

// The ISB filter (ALGORITHM.md §4) on width x height pixels of `channels` floats
// (values[p * channels + c]), guided by packed 8-bit guides; returns the filtered values.
// Computed in float in the shaders' order of summation, so that the 8-bit rounding of guides
// decides the same way as on a GPU. With sigma_s_confident > 0 the guides' fourth byte is a
// confidence (255 = 1), averaged down with the guide's weights and kept up, and each pixel's
// spatial sigma falls from sigma_s at confidence 0.5 to sigma_s_confident at 0.7
// (isb_weights.glsl); otherwise the fourth byte is ignored and left 0.
std::vector<float> isb_filter_cpu(std::vector<std::uint32_t> guide, std::vector<float> values,
                                  int width, int height, int channels, double sigma_i,
                                  double sigma_s, double sigma_s_confident = 0);

// Winner takes all with the parabola step on one pixel's N costs: the distance in metres.
float winner_take_all_cpu(const float* costs, const DepthOptions& options);

// The confidence of one pixel's N costs (wta.glsl): sqrt(ratio x sharpness), with the peak ratio
// 1 - lowest / second (second: the second lowest local minimum, or the highest cost where there
// is one minimum; 0 for a flat curve) and the sharpness k / (k + lowest) (k: the curvature at the
// first lowest candidate, one-sided at the ends).
float cost_confidence_cpu(const float* costs, int n);

// The raw agreement factor (wta.glsl) of one pixel: its filtered curve's first lowest candidate
// i*, and its raw curve (`raw`, the same N candidates before the filter) with lowest L (first at
// candidate j) and highest H: where j < i* (the raw curve puts the surface nearer),
// exp(-(d p / tolerance)^2), d = (raw[i*] - L) / (H - L) (0 where H = L), p = 1 - L / H (0 where
// H is 0); 1 where j >= i* or tolerance is 0 (off).
float raw_agreement_cpu(const float* filtered, const float* raw, int n, double tolerance);

// The coarse agreement factor (coarse_agreement.comp) of every pixel of a width x height distance
// map (metres), from the ISB filter's level 1 (level_width x level_height pixels of N costs,
// level[p * N + i]): exp(-(delta / options.coarse_agreement)^2), delta between the pixel's inverse
// distance and the winner of its 8 x 8 block's level-1 curves summed in row order.
std::vector<float> coarse_agreement_cpu(const std::vector<float>& level, int level_width,
                                        int level_height, const FloatImage& distance,
                                        const DepthOptions& options);

}  // namespace omnisweep::depth
