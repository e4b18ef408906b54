#include "server/pipeline/gpu_frame.h"

namespace omnisweep::pipeline {

GpuFrame::GpuFrame(gpu::Context& context, depth::DepthEstimator& estimator,
                   stitch::Stitcher& stitcher)
    : estimator_(&estimator), stitcher_(&stitcher), sequence_(context) {}

stitch::Panorama GpuFrame::run(std::span<const Rgb8View> matching,
                               std::span<const Rgb8View> color) {
  estimator_->upload(matching);
  stitcher_->upload_color(color);
  sequence_.begin();
  estimator_->record(sequence_);
  stitcher_->record(sequence_, estimator_->distance_buffer(), &estimator_->confidence_buffer());
  sequence_.submit_and_wait();
  stitch::Panorama panorama = stitcher_->download();
  panorama.stage_ms = sequence_.stage_ms();
  return panorama;
}

}  // namespace omnisweep::pipeline
