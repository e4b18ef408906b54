// One frame as one GPU submission: the camera images go up, depth (DepthEstimator) and stitching
// (Stitcher) are recorded into the same command buffer so the depth maps never leave the GPU, the
// host waits once, and the panorama comes down. omnisweep-server, omnisweep-process and the cost
// model run frames this way.
#pragma once

#include <optional>
#include <vector>

#include "omnisweep/gpu/sequence.h"
#include "server/depth/depth_estimator.h"
#include "server/depth/gpu_photometric_correction.h"
#include "server/stitch/stitcher.h"

namespace omnisweep::pipeline {

class GpuFrame {
 public:
  // Both must outlive this, and be made for the same references.
  GpuFrame(gpu::Context& context, depth::DepthEstimator& estimator, stitch::Stitcher& stitcher);

  // `matching`: every camera at the matching resolution; `color`: the references at the colour
  // resolution. With `photometry` (DepthOptions::correct_photometry: PhotometricCorrector::fit),
  // the first dispatch undoes its responses in both on the GPU (stage "photometry"). The
  // panorama's stage_ms holds the GPU time of every stage, depth's included.
  stitch::Panorama run(std::span<const Rgb8View> matching, std::span<const Rgb8View> color,
                       const depth::PhotometryFit* photometry = nullptr);

 private:
  gpu::Context* context_;
  depth::DepthEstimator* estimator_;
  stitch::Stitcher* stitcher_;
  gpu::Sequence sequence_;
  // Made on the first frame with a fit (their per-pixel tables take a while).
  std::optional<depth::GpuPhotometricCorrection> matching_correction_;
  std::optional<depth::GpuPhotometricCorrection> color_correction_;
};

}  // namespace omnisweep::pipeline
