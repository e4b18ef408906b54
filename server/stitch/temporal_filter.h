// A temporal filter for panorama streams (omnisweep-server --temporal, omnisweep-process
// --temporal): each pixel's inverse distance becomes the running mean over the frames since it
// last changed, at most TemporalOptions::max_frames of them, so a static scene stops flickering.
// Nothing ghosts: a pixel starts again where its colour or its distance moved, and every pixel
// does where much of the panorama's colour moved at once (the rig or the light moved). Where the
// frame's confidence is low (a plane fill's or an inpainting's guess), a distance that jumps is
// first taken for noise in the guess and averaged; the pixel starts again when the next frame
// confirms the jump. It runs on the stitched panorama, on the GPU, after the merge
// (temporal_changes.comp, temporal_filter.comp); temporal_filter_cpu is the plain C++ reference.
#pragma once

#include <cstdint>
#include <vector>

#include "omnisweep/gpu/kernel.h"
#include "omnisweep/gpu/sequence.h"
#include "omnisweep/image/image.h"

namespace omnisweep::stitch {

struct TemporalOptions {
  int max_frames = 8;             // frames in the running mean at most (1: no filtering)
  double jump = 0.1;              // 1/m: a new inverse distance this far from the mean restarts
  double color_threshold = 20.0;  // sum of |dR| + |dG| + |dB| (8-bit) that restarts a pixel
  double reset_share = 0.05;      // share of pixels whose colour moved that restarts them all
  // Confidence (0-1) from which a jump restarts a pixel at once. Below it (by default the plane
  // fill's threshold: the distance is a guess from the planes around) a jump restarts only when
  // the next frame's distance is within `jump` of the first jumped one; otherwise both join the
  // mean. 0: every jump restarts at once.
  double confident = 0.05;
  // Throws std::invalid_argument naming the field, its value and what is allowed.
  void check() const;
};

// The filter's memory of the frames so far, per pixel.
struct TemporalState {
  std::vector<float> mean_inverse;
  std::vector<float> count;
  std::vector<std::uint32_t> previous_color;  // packed RGB
  std::vector<float> pending_inverse;         // an unconfirmed jump's inverse distance, or 0
  bool started = false;
};

// One frame through the filter, in place: `distance` (metres, 0 = none) becomes the filtered
// distance; `color` is the frame's colour panorama and `confidence` its confidence (0-1). Float
// arithmetic in the kernel's order.
void temporal_filter_cpu(TemporalState& state, FloatImage& distance, const Rgb8Image& color,
                         const FloatImage& confidence, const TemporalOptions& options);

class TemporalFilter {
 public:
  TemporalFilter(gpu::Context& context, int width, int height, const TemporalOptions& options);

  // Records the filter into `seq` (after what writes `distance`, `color` and `confidence`,
  // panorama-sized floats, packed RGB and floats): `distance` is filtered in place.
  void record(gpu::Sequence& seq, gpu::Buffer& distance, const gpu::Buffer& color,
              const gpu::Buffer& confidence);
  // The next frame starts the filter again everywhere.
  void reset() { started_ = false; }
  const TemporalOptions& options() const { return options_; }

 private:
  TemporalOptions options_;
  std::uint32_t width_, height_, pixels_;
  gpu::Buffer mean_inverse_;
  gpu::Buffer count_;
  gpu::Buffer previous_color_;
  gpu::Buffer pending_inverse_;
  gpu::Buffer changed_;
  gpu::Kernel changes_;
  gpu::Kernel filter_;
  bool started_ = false;
};

}  // namespace omnisweep::stitch
