#include "server/synthetic/photometric.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace omnisweep::synthetic {
namespace {

// SplitMix64: a counter-based generator, so every pixel draws its own noise from (seed, index)
// in parallel, and the same seed gives the same frame on every standard library (the <random>
// distributions are implementation-defined).
std::uint64_t mix(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

// Uniform in [0, 1) from 53 bits.
double uniform(std::uint64_t bits) { return double(bits >> 11) * 0x1.0p-53; }

double uniform_in(std::uint64_t bits, double lo, double hi) {
  return lo + (hi - lo) * uniform(bits);
}

void check_range(const char* field, double value, double lo, double hi) {
  if (!(value >= lo && value <= hi)) {
    throw std::invalid_argument("photometric " + std::string(field) + " " + std::to_string(value) +
                                " must be within [" + std::to_string(lo) + ", " +
                                std::to_string(hi) + "]");
  }
}

}  // namespace

PhotometricOptions PhotometricOptions::realistic() {
  PhotometricOptions o;
  o.gain_spread = 0.25;
  o.color_cast = 0.06;
  o.vignetting_min = 0.45;
  o.vignetting_max = 0.65;
  return o;
}

void PhotometricOptions::check() const {
  check_range("gain_spread", gain_spread, 0.0, 0.9);
  check_range("color_cast", color_cast, 0.0, 0.5);
  check_range("vignetting_min", vignetting_min, 0.05, 1.0);
  check_range("vignetting_max", vignetting_max, vignetting_min, 1.0);
  check_range("vignetting_angle_deg", vignetting_angle_deg, 1.0, 180.0);
  check_range("noise_sigma", noise_sigma, 0.0, 64.0);
}

CameraResponse draw_camera_response(const PhotometricOptions& options, std::uint64_t seed,
                                    int camera) {
  std::uint64_t state = mix(seed ^ 0x70686f746fULL) + std::uint64_t(camera) * 0x100;
  auto next = [&] { return mix(state++); };
  CameraResponse r;
  const double gain = uniform_in(next(), 1 - options.gain_spread, 1 + options.gain_spread);
  for (double& g : r.gain)
    g = gain * uniform_in(next(), 1 - options.color_cast, 1 + options.color_cast);
  r.vignetting = uniform_in(next(), options.vignetting_min, options.vignetting_max);
  return r;
}

void apply_camera_response(const PhotometricOptions& options, const CameraResponse& response,
                           const RigCamera& camera, std::uint64_t noise_seed,
                           const RgbFloatImage& radiance, Rgb8Image* image) {
  if (!options.any()) return;
  if (radiance.width() != image->width() || radiance.height() != image->height())
    throw std::invalid_argument(
        "apply_camera_response: the radiance is " + std::to_string(radiance.width()) + "x" +
        std::to_string(radiance.height()) + ", the image " + std::to_string(image->width()) + "x" +
        std::to_string(image->height()));
  const double falloff = 1.0 - response.vignetting;
  const double angle_scale = 180.0 / (options.vignetting_angle_deg * std::numbers::pi);
  const std::uint64_t frame_key = mix(noise_seed);
#pragma omp parallel for schedule(dynamic, 8)
  for (int v = 0; v < image->height(); ++v) {
    for (int u = 0; u < image->width(); ++u) {
      double brightness = 1.0;
      if (falloff > 0) {
        Eigen::Vector3d ray;  // no ray: outside the lens, where the image is black anyway
        if (camera.model.unproject(Eigen::Vector2d(u, v), &ray)) {
          const double a = std::acos(std::clamp(ray.normalized().z(), -1.0, 1.0)) * angle_scale;
          brightness = std::max(0.0, 1.0 - falloff * a * a);
        }
      }
      const std::uint64_t pixel = std::uint64_t(v) * image->width() + u;
      for (int k = 0; k < 3; ++k) {
        double value = 255.0 * radiance(u, v, k) * response.gain[k] * brightness;
        if (options.noise_sigma > 0) {
          // Box-Muller from two independent draws of this pixel and channel.
          const std::uint64_t key = frame_key ^ (pixel * 3 + k) * 0x9e3779b97f4a7c15ull;
          const double u1 = 1.0 - uniform(mix(key)), u2 = uniform(mix(key + 1));
          value += options.noise_sigma * std::sqrt(-2.0 * std::log(u1)) *
                   std::cos(2.0 * std::numbers::pi * u2);
        }
        (*image)(u, v, k) = std::uint8_t(std::lround(std::clamp(value, 0.0, 255.0)));
      }
    }
  }
}

}  // namespace omnisweep::synthetic
