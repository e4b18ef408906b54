// The plane fill (StitchOptions::plane_fill, --plane-fill; docs/accuracy.md): where the
// panorama's confidence is low, the ISB filter's fill comes from beyond the surface (a plain
// ceiling filled from the textured far end of the hall, a floor from the object beside it). The
// fill replaces those inverse distances with a plane fitted to the confident pixels around
// them, weighted by colour closeness: a plane seen from the viewpoint has an inverse distance
// linear in the unit ray, so a slanted floor or ceiling is followed where a constant fill is not.
// It runs on the merged panorama, on the GPU (plane_fill.comp); plane_fill_cpu is the plain C++
// reference.
#pragma once

#include <cstdint>

#include "omnisweep/gpu/buffer.h"
#include "omnisweep/gpu/kernel.h"
#include "omnisweep/gpu/sequence.h"
#include "omnisweep/image/image.h"

namespace omnisweep::stitch {

// The fit's settings at a 2048-pixel-wide panorama (steps and sigma_s scale with the width):
// 17 x 17 taps 12 pixels apart (about +-17 degrees), sigma_s 48 pixels, sigma_c 16 levels, the
// pixels of confidence 0.2 or more as support, a ridge of 1e-3 on the plane's slope; then
// `refits` fits more, each weighting the support by exp(-r^2 / 2 tau^2) too, r its inverse
// distance's residual (m^-1) from the last plane, so that support of like colour on another
// surface drops out. Measured on blender-hall and the synthetic frames (docs/accuracy.md).
struct PlaneFillParams {
  int step = 12;
  int taps = 8;
  double sigma_s = 48.0;
  double sigma_c = 16.0;
  double support = 0.2;
  double lambda = 1e-3;
  int refits = 2;
  double tau = 0.02;
  // For a panorama `width` pixels wide: step and sigma_s scaled from 2048 pixels.
  static PlaneFillParams for_width(int width);
};

// `distance` (metres, 0 = none) where `confidence` < fill_below, filled as plane_fill.comp does,
// in float arithmetic in its order; `rgb` is the panorama's colour. Inverse distances are clamped
// to the sweep's range [1 / max_distance, 1 / min_distance].
FloatImage plane_fill_cpu(const Rgb8Image& rgb, const FloatImage& distance,
                          const FloatImage& confidence, double fill_below, double min_distance,
                          double max_distance);

class PlaneFill {
 public:
  PlaneFill(gpu::Context& context, int width, int height, double fill_below, double min_distance,
            double max_distance);

  // Records the fill into `seq` after what writes its inputs (panorama-sized packed RGB,
  // float distances and confidences): `out` gets the filled distances.
  void record(gpu::Sequence& seq, const gpu::Buffer& color, const gpu::Buffer& distance,
              const gpu::Buffer& confidence, gpu::Buffer& out) const;

 private:
  int width_, height_;
  double fill_below_, min_distance_, max_distance_;
  gpu::Buffer table_;   // the rays and spatial weights (plane_fill.glsl)
  gpu::Buffer planes_;  // per cell of 4 x 4 pixels, (a, b) of its plane
  gpu::Kernel fit_;     // plane_fit.comp
  gpu::Kernel fill_;    // plane_fill.comp
};

}  // namespace omnisweep::stitch
