// Evaluation as in the paper's tables (ALGORITHM.md §6): inverse distance E = |1/D - 1/D*| per
// pixel (MAE, RMSE, share of pixels with E > 0.1 and E > 0.4 m^-1), colour PSNR, and SSIM as
// scikit-image computes it by default (7x7 uniform window, sample covariance, images in [0, 1],
// K1 = 0.01, K2 = 0.03, channels averaged, a 3-pixel border left out).
#pragma once

#include "omnisweep/image/image.h"

namespace omnisweep::stitch {

struct PanoramaMetrics {
  double mae = 0;      // m^-1
  double rmse = 0;     // m^-1
  double bad_0_1 = 0;  // share of pixels, 0..1
  double bad_0_4 = 0;
  double psnr = 0;  // dB
  double ssim = 0;
};

// `distance`: metres (0 = none, counted as inverse distance 0); `inverse_truth`: m^-1.
PanoramaMetrics evaluate_panorama(const Rgb8Image& rgb, const FloatImage& distance,
                                  const Rgb8Image& rgb_truth, const FloatImage& inverse_truth);
double psnr(const Rgb8Image& a, const Rgb8Image& b);
double ssim(const Rgb8Image& a, const Rgb8Image& b);

}  // namespace omnisweep::stitch
