#include "server/stitch/panorama_metrics.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <vector>

#include "server/stitch/same_size.h"

namespace omnisweep::stitch {
namespace {

// Mean of `f` over the 7x7 window around every pixel with a 3-pixel margin (what scikit-image
// keeps after cropping), via a summed-area table.
std::vector<double> window_means(const std::vector<double>& f, int w, int h) {
  std::vector<double> sat(std::size_t(w + 1) * (h + 1), 0.0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      sat[(y + 1) * std::size_t(w + 1) + x + 1] =
          f[std::size_t(y) * w + x] + sat[y * std::size_t(w + 1) + x + 1] +
          sat[(y + 1) * std::size_t(w + 1) + x] - sat[y * std::size_t(w + 1) + x];
  std::vector<double> out;
  for (int y = 3; y < h - 3; ++y)
    for (int x = 3; x < w - 3; ++x) {
      auto at = [&](int yy, int xx) { return sat[std::size_t(yy) * (w + 1) + xx]; };
      out.push_back((at(y + 4, x + 4) - at(y - 3, x + 4) - at(y + 4, x - 3) + at(y - 3, x - 3)) /
                    49.0);
    }
  return out;
}

}  // namespace

double psnr(const Rgb8Image& a, const Rgb8Image& b) {
  require_same_size("PSNR", {sized("ground-truth colour", b), sized("colour panorama", a)});
  double mse = 0;
  for (std::size_t i = 0; i < a.size(); ++i) mse += std::pow(double(a.data()[i]) - b.data()[i], 2);
  mse /= double(a.size());
  return mse > 0 ? 10.0 * std::log10(255.0 * 255.0 / mse) : std::numeric_limits<double>::infinity();
}

double ssim(const Rgb8Image& a, const Rgb8Image& b) {
  require_same_size("SSIM", {sized("ground-truth colour", b), sized("colour panorama", a)});
  const int w = a.width(), h = a.height();
  if (w < 7 || h < 7) throw std::invalid_argument("SSIM needs images of at least 7x7 pixels");
  const double c1 = 0.01 * 0.01, c2 = 0.03 * 0.03, cov_norm = 49.0 / 48.0;
  double total = 0;
  for (int c = 0; c < 3; ++c) {
    std::vector<double> x(std::size_t(w) * h), y(x.size()), xx(x.size()), yy(x.size()),
        xy(x.size());
    for (std::size_t i = 0; i < x.size(); ++i) {
      x[i] = a.data()[3 * i + c] / 255.0;
      y[i] = b.data()[3 * i + c] / 255.0;
      xx[i] = x[i] * x[i];
      yy[i] = y[i] * y[i];
      xy[i] = x[i] * y[i];
    }
    const auto ux = window_means(x, w, h), uy = window_means(y, w, h), uxx = window_means(xx, w, h),
               uyy = window_means(yy, w, h), uxy = window_means(xy, w, h);
    double sum = 0;
    for (std::size_t i = 0; i < ux.size(); ++i) {
      const double vx = cov_norm * (uxx[i] - ux[i] * ux[i]),
                   vy = cov_norm * (uyy[i] - uy[i] * uy[i]);
      const double vxy = cov_norm * (uxy[i] - ux[i] * uy[i]);
      sum += (2 * ux[i] * uy[i] + c1) * (2 * vxy + c2) /
             ((ux[i] * ux[i] + uy[i] * uy[i] + c1) * (vx + vy + c2));
    }
    total += sum / double(ux.size());
  }
  return total / 3.0;
}

PanoramaMetrics evaluate_panorama(const Rgb8Image& rgb, const FloatImage& distance,
                                  const Rgb8Image& rgb_truth, const FloatImage& inverse_truth) {
  require_same_size("evaluation", {sized("ground-truth inverse distance", inverse_truth),
                                   sized("distance panorama", distance)});
  PanoramaMetrics m;
  const std::size_t n = distance.size();
  const int width = distance.width(), height = distance.height();
  std::array<std::size_t, 8> band_pixels{};
  for (int y = 0; y < height; ++y) {
    const auto band = std::size_t(std::int64_t(y) * 8 / height);
    for (int x = 0; x < width; ++x) {
      const std::size_t i = std::size_t(y) * std::size_t(width) + std::size_t(x);
      const double d = distance.data()[i];
      const double e = std::abs((d > 0 ? 1.0 / d : 0.0) - inverse_truth.data()[i]);
      m.mae += e;
      m.rmse += e * e;
      m.bad_0_1 += e > 0.1;
      m.bad_0_4 += e > 0.4;
      m.mae_by_eighth[band] += e;
    }
    band_pixels[band] += std::size_t(width);
  }
  for (std::size_t b = 0; b < band_pixels.size(); ++b) {
    if (band_pixels[b] > 0) m.mae_by_eighth[b] /= double(band_pixels[b]);
  }
  m.mae /= double(n);
  m.rmse = std::sqrt(m.rmse / double(n));
  m.bad_0_1 /= double(n);
  m.bad_0_4 /= double(n);
  m.psnr = psnr(rgb, rgb_truth);
  m.ssim = ssim(rgb, rgb_truth);
  return m;
}

namespace {

// The MAE of the pixels left after removing the first order.size() * x of `order` from the
// end, for each x of `removed`; `order` is best first.
std::vector<double> remaining_mae(const std::vector<double>& error,
                                  const std::vector<std::size_t>& order,
                                  const std::vector<double>& removed) {
  // Prefix sums of the errors in order: the MAE of the first k is sums[k] / k.
  std::vector<double> sums(order.size() + 1, 0.0);
  for (std::size_t i = 0; i < order.size(); ++i) sums[i + 1] = sums[i] + error[order[i]];
  std::vector<double> out;
  for (const double x : removed) {
    const auto kept =
        std::max<std::size_t>(1, std::size_t(std::llround(double(order.size()) * (1.0 - x))));
    out.push_back(sums[kept] / double(kept));
  }
  return out;
}

}  // namespace

Sparsification sparsification(const FloatImage& distance, const FloatImage& confidence,
                              const FloatImage& inverse_truth, int steps) {
  require_same_size("sparsification", {sized("ground-truth inverse distance", inverse_truth),
                                       sized("distance panorama", distance),
                                       sized("confidence panorama", confidence)});
  if (steps < 2) throw std::invalid_argument("sparsification: steps must be at least 2");
  const std::size_t n = distance.size();
  std::vector<double> error(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double d = distance.data()[i];
    error[i] = std::abs((d > 0 ? 1.0 / d : 0.0) - inverse_truth.data()[i]);
  }
  Sparsification s;
  for (int i = 0; i < steps; ++i) s.removed.push_back(double(i) / steps);
  s.removed.push_back(
      0.2);  // keeps the 80 % most confident: mae_at_80 (and the oracle's), taken off below
  std::vector<std::size_t> by_confidence(n), by_error(n);
  std::iota(by_confidence.begin(), by_confidence.end(), 0);
  std::iota(by_error.begin(), by_error.end(), 0);
  // Ties keep pixel order, so the curve is deterministic.
  std::stable_sort(by_confidence.begin(), by_confidence.end(), [&](std::size_t a, std::size_t b) {
    return confidence.data()[a] > confidence.data()[b];
  });
  std::stable_sort(by_error.begin(), by_error.end(),
                   [&](std::size_t a, std::size_t b) { return error[a] < error[b]; });
  s.mae = remaining_mae(error, by_confidence, s.removed);
  s.oracle = remaining_mae(error, by_error, s.removed);
  s.removed.pop_back();
  s.mae_at_80 = s.mae.back();
  s.oracle_at_80 = s.oracle.back();
  s.mae.pop_back();
  s.oracle.pop_back();
  s.monotonic = true;
  for (std::size_t i = 0; i < s.mae.size(); ++i) {
    s.ause += (s.mae[i] - s.oracle[i]) / steps;
    if (i > 0 && s.mae[i] > s.mae[i - 1]) s.monotonic = false;
  }
  return s;
}

double flicker(const FloatImage& previous_inverse, const FloatImage& inverse,
               const FloatImage& previous_truth, const FloatImage& truth) {
  require_same_size("flicker",
                    {sized("ground truth", truth), sized("previous panorama", previous_inverse),
                     sized("panorama", inverse), sized("previous ground truth", previous_truth)});
  double sum = 0;
  std::size_t count = 0;
  for (std::size_t i = 0; i < truth.size(); ++i) {
    if (std::abs(double(truth.data()[i]) - previous_truth.data()[i]) > 1e-6) continue;
    sum += std::abs(double(inverse.data()[i]) - previous_inverse.data()[i]);
    ++count;
  }
  return count > 0 ? sum / double(count) : 0.0;
}

}  // namespace omnisweep::stitch
