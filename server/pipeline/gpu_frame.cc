#include "server/pipeline/gpu_frame.h"

namespace omnisweep::pipeline {

GpuFrame::GpuFrame(gpu::Context& context, depth::DepthEstimator& estimator,
                   stitch::Stitcher& stitcher)
    : context_(&context), estimator_(&estimator), stitcher_(&stitcher), sequence_(context) {}

stitch::Panorama GpuFrame::run(std::span<const Rgb8View> matching, std::span<const Rgb8View> color,
                               const depth::PhotometryFit* photometry) {
  estimator_->upload(matching);
  stitcher_->upload_color(color);
  sequence_.begin();
  if (photometry) {
    if (!matching_correction_) {
      matching_correction_.emplace(*context_, estimator_->rig());
      color_correction_.emplace(*context_, stitcher_->color_rig(), stitcher_->references());
    }
    sequence_.begin_stage("photometry");
    matching_correction_->record(sequence_, estimator_->image_buffer(), *photometry);
    color_correction_->record(sequence_, stitcher_->color_buffer(), *photometry);
    sequence_.end_stage();
  }
  estimator_->record(sequence_);
  stitcher_->record(sequence_, estimator_->distance_buffer(), &estimator_->confidence_buffer());
  sequence_.submit_and_wait();
  stitch::Panorama panorama = stitcher_->download();
  panorama.stage_ms = sequence_.stage_ms();
  return panorama;
}

}  // namespace omnisweep::pipeline
