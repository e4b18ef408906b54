// The photometric correction (photometric_model.h) on the GPU: undoes a fit's gains and vignetting
// in camera images already uploaded as packed RGBA8 (DepthEstimator's matching images, Stitcher's
// colour images), in place, as the first dispatch of a frame. On the host the same correction
// costs ~40 ms per frame on 2 cores here (4 matching and 2 colour images); on the GPU it is one
// pass over the pixels.
#pragma once

#include <vector>

#include "omnisweep/gpu/buffer.h"
#include "omnisweep/gpu/kernel.h"
#include "omnisweep/gpu/sequence.h"
#include "omnisweep/rig/rig.h"
#include "server/depth/photometric_model.h"

namespace omnisweep::depth {

class GpuPhotometricCorrection {
 public:
  // For a buffer holding `cameras` of `rig` (all its cameras in order when empty), image after
  // image; they must share one size. Throws std::invalid_argument otherwise.
  GpuPhotometricCorrection(gpu::Context& context, const Rig& rig, std::vector<int> cameras = {});

  // Records the correction of `images` (packed RGBA8, as above) by `fit`, and a barrier. The fit's
  // responses are written now: the sequence must be submitted before the next record().
  void record(gpu::Sequence& seq, gpu::Buffer& images, const PhotometryFit& fit);

 private:
  std::vector<int> cameras_;
  int width_ = 0;
  int height_ = 0;
  gpu::Kernel kernel_;
  gpu::Buffer angles_;
  gpu::Buffer responses_;
};

}  // namespace omnisweep::depth
