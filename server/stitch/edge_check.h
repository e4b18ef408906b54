// The edge check (StitchOptions::edge_check, --edge-check; docs/accuracy.md, "Confidence"): the
// ISB filter's coarse levels carry a foreground's sharp cost curve into the plain background
// beside it (the synthetic ceiling beside its poles), and there the curve, and so the confidence,
// is as sharp as on the foreground. What marks such a carried distance is a depth step with no
// colour step: within 3 x 3 pixels the inverse distance changes by more than `step` while no
// colour channel changes by `color` levels. The panorama is cut into blocks; a block holding
// such a step marks its neighbourhood, and every pixel within `reach` blocks of a marked block
// has its confidence multiplied by `factor`. Distances are not changed. Two passes on the GPU
// (edge_marks.comp, edge_check.comp); edge_check_cpu is the plain C++ reference.
#pragma once

#include <cstdint>

#include "omnisweep/gpu/buffer.h"
#include "omnisweep/gpu/kernel.h"
#include "omnisweep/gpu/sequence.h"
#include "omnisweep/image/image.h"

namespace omnisweep::stitch {

// The settings at a 2048-pixel-wide panorama (the block scales with the width): blocks of 8 x 8
// pixels, 3 blocks of reach (24-31 pixels), steps of 0.05 m^-1 (about one candidate spacing of
// the default sweep) against colour changes under 8 levels, and a factor of 0.1. Measured on the
// synthetic rig and blender-hall (docs/accuracy.md).
struct EdgeCheckParams {
  int block = 8;
  int reach = 3;
  double step = 0.05;
  double color = 8.0;
  double factor = 0.1;
  // For a panorama `width` pixels wide: the block scaled from 2048 pixels (at least 1).
  static EdgeCheckParams for_width(int width);
  // Throws std::invalid_argument naming what is out of range.
  void check() const;
};

// `confidence` after the check, as edge_marks.comp and edge_check.comp make it: `rgb` the
// panorama's colour, `distance` its distances (metres, 0 = none; pixels without one neither mark
// nor count as a neighbour). Columns wrap around (the panorama is 360 degrees), rows do not.
// Throws std::invalid_argument on bad params or sizes that differ.
FloatImage edge_check_cpu(const Rgb8Image& rgb, const FloatImage& distance,
                          const FloatImage& confidence, const EdgeCheckParams& params);

class EdgeCheck {
 public:
  EdgeCheck(gpu::Context& context, int width, int height, const EdgeCheckParams& params);

  // Records the check into `seq` after what writes its inputs (panorama-sized packed RGB and
  // float distances): `confidence` is changed in place.
  void record(gpu::Sequence& seq, const gpu::Buffer& color, const gpu::Buffer& distance,
              gpu::Buffer& confidence) const;

 private:
  int width_, height_;
  EdgeCheckParams params_;
  gpu::Buffer marks_;         // one uint per block: 1 where it holds a step without a colour step
  gpu::Kernel marks_kernel_;  // edge_marks.comp
  gpu::Kernel apply_;         // edge_check.comp
};

}  // namespace omnisweep::stitch
