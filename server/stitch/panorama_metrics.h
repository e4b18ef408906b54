// Evaluation as in the paper's tables (ALGORITHM.md §6): inverse distance E = |1/D - 1/D*| per
// pixel (MAE, RMSE, share of pixels with E > 0.1 and E > 0.4 m^-1), colour PSNR, and SSIM as
// scikit-image computes it by default (7x7 uniform window, sample covariance, images in [0, 1],
// K1 = 0.01, K2 = 0.03, channels averaged, a 3-pixel border left out).
#pragma once

#include <array>
#include <vector>

#include "omnisweep/image/image.h"

namespace omnisweep::stitch {

struct PanoramaMetrics {
  double mae = 0;      // m^-1
  double rmse = 0;     // m^-1
  double bad_0_1 = 0;  // share of pixels, 0..1
  double bad_0_4 = 0;
  double psnr = 0;  // dB
  double ssim = 0;
  // The MAE of each eighth of the panorama's rows, the top (22.5 degrees around the zenith) first:
  // where the error sits by elevation. With sensor noise a plain ceiling holds no information,
  // and its guess can move the MAE of all as much as the methods differ (docs/accuracy.md, stop
  // 47).
  std::array<double, 8> mae_by_eighth{};
};

// `distance`: metres (0 = none, counted as inverse distance 0); `inverse_truth`: m^-1.
PanoramaMetrics evaluate_panorama(const Rgb8Image& rgb, const FloatImage& distance,
                                  const Rgb8Image& rgb_truth, const FloatImage& inverse_truth);
double psnr(const Rgb8Image& a, const Rgb8Image& b);

// How well a confidence ranks the errors (a sparsification curve): the pixels sorted by
// confidence, the least confident share x removed, the MAE of the rest, for x = 0, 1/steps, ...
// (steps - 1)/steps; the oracle removes the largest errors instead. AUSE is the area between the
// two curves over x in [0, 1) (rectangles of width 1/steps), in m^-1.
struct Sparsification {
  std::vector<double> removed;  // x
  std::vector<double> mae;      // by confidence
  std::vector<double> oracle;   // by error
  double ause = 0;
  double mae_at_80 = 0;     // the MAE of the 80 % most confident pixels
  double oracle_at_80 = 0;  // the oracle's: the MAE of the 80 % smallest errors, the least any
                            // confidence can give mae_at_80 on these distances
  bool monotonic = false;   // whether the curve never rises
};
Sparsification sparsification(const FloatImage& distance, const FloatImage& confidence,
                              const FloatImage& inverse_truth, int steps = 20);

// Flicker between consecutive frames: the mean |change of estimated inverse distance| (m^-1)
// over the pixels whose true inverse distance did not change (within 1e-6). All four in m^-1;
// 0 where no pixel's truth held still.
double flicker(const FloatImage& previous_inverse, const FloatImage& inverse,
               const FloatImage& previous_truth, const FloatImage& truth);
double ssim(const Rgb8Image& a, const Rgb8Image& b);

}  // namespace omnisweep::stitch
