// Fixtures for the depth tests and the benchmark: synthetic frames at the matching resolution
// with exact per-camera ground truth, and the GPU ISB filter run on host data.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "omnisweep/gpu/context.h"
#include "server/depth/isb_filter.h"
#include "server/synthetic/synthetic_rig.h"

namespace omnisweep::depth::fixtures {

struct SyntheticDepthCase {
  synthetic::SyntheticRig rig;                    // calibrated at the matching resolution
  std::vector<Rgb8Image> images;                  // per camera
  std::vector<FloatImage> inverse_gt;             // per camera, m^-1 (0 outside the lens)
  std::vector<std::optional<Gray8Image>> usable;  // lens masks

  std::vector<Rgb8View> image_views() const;
};

// `photometric`: the cameras' gains, casts and vignetting (none by default).
SyntheticDepthCase render_depth_case(int size, int frame = 0, std::uint64_t seed = 1,
                                     const synthetic::PhotometricOptions& photometric = {});

// Inverse-distance errors of a fisheye distance map (metres) against its ground truth (m^-1),
// over the usable pixels that have one.
struct Accuracy {
  double mae = 0, bad_0_1 = 0, bad_0_4 = 0;
  long pixels = 0;
};
Accuracy inverse_distance_accuracy(const FloatImage& distance, const FloatImage& inverse_gt,
                                   const Gray8Image& usable);

// Images of one size one after another as packed RGBA8 (reproject::pack_rgba8), as the depth
// kernels read them, and back (alpha dropped).
std::vector<std::uint32_t> packed_images(std::span<const Rgb8View> images);
std::vector<Rgb8Image> unpacked_images(std::span<const std::uint32_t> packed, int width,
                                       int height);

// Filters `values` (width x height x channels) guided by `guide` on the GPU.
std::vector<float> isb_filter_gpu(gpu::Context& context, const std::vector<std::uint32_t>& guide,
                                  const std::vector<float>& values, int width, int height,
                                  int channels, const IsbParams& params);

}  // namespace omnisweep::depth::fixtures
