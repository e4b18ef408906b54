// Runs one pass that rewrites a panorama's distance in place (the stitcher's fills) on its own:
// the distance and confidence uploaded, `record(seq, distance, confidence)` recorded into one
// submission, the distance downloaded.
#pragma once

#include <utility>

#include "omnisweep/gpu/buffer.h"
#include "omnisweep/gpu/sequence.h"
#include "omnisweep/image/image.h"

namespace omnisweep::testing {

template <typename Record>
FloatImage run_panorama_pass(gpu::Context& context, const FloatImage& distance,
                             const FloatImage& confidence, Record&& record) {
  const vk::DeviceSize bytes = vk::DeviceSize(distance.size()) * 4;
  gpu::Buffer on_gpu(context, bytes), confidence_on_gpu(context, bytes);
  on_gpu.upload(distance.data(), bytes);
  confidence_on_gpu.upload(confidence.data(), bytes);
  gpu::Sequence seq(context);
  seq.begin();
  std::forward<Record>(record)(seq, on_gpu, confidence_on_gpu);
  seq.submit_and_wait();
  FloatImage result(distance.width(), distance.height());
  on_gpu.download(result.data(), bytes);
  return result;
}

}  // namespace omnisweep::testing
