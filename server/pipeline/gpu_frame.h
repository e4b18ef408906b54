// One frame as one GPU submission: the camera images go up, depth (DepthEstimator) and stitching
// (Stitcher) are recorded into the same command buffer so the depth maps never leave the GPU, the
// host waits once, and the panorama comes down. omnisweep-server, omnisweep-process and the cost
// model run frames this way.
#pragma once

#include <vector>

#include "omnisweep/gpu/sequence.h"
#include "server/depth/depth_estimator.h"
#include "server/stitch/stitcher.h"

namespace omnisweep::pipeline {

class GpuFrame {
 public:
  // Both must outlive this, and be made for the same references.
  GpuFrame(gpu::Context& context, depth::DepthEstimator& estimator, stitch::Stitcher& stitcher);

  // `matching`: every camera at the matching resolution; `color`: the references at the colour
  // resolution. The panorama's stage_ms holds the GPU time of every stage, depth's included.
  stitch::Panorama run(std::span<const Rgb8View> matching, std::span<const Rgb8View> color);

 private:
  depth::DepthEstimator* estimator_;
  stitch::Stitcher* stitcher_;
  gpu::Sequence sequence_;
};

}  // namespace omnisweep::pipeline
