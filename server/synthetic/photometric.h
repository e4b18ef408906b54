// What a real rig's cameras do to light that the renderer does not: a per-camera gain (exposure
// and sensor sensitivity), a per-camera colour cast (white balance), radial lens vignetting and
// per-frame sensor noise. Applied to the rendered colour before it is rounded to 8 bits, as a
// sensor quantises after its gain and noise: rounding the render first and the response after
// would give every camera the same 8-bit steps on smooth shading, a texture fixed in the scene
// that noise dithers away on a real sensor (docs/accuracy.md, "Sensor noise"). A gain in linear
// light is a gain of the gamma-encoded values too, so this is the same model, at the strong end.
// The ground truth panorama keeps the scene's own colours.
#pragma once

#include <cstdint>

#include "omnisweep/image/image.h"
#include "omnisweep/rig/rig.h"

namespace omnisweep::synthetic {

struct PhotometricOptions {
  double gain_spread = 0.0;  // per-camera gain uniform in [1 - s, 1 + s]
  double color_cast = 0.0;   // per-camera, per-channel factor uniform in [1 - c, 1 + c]
  // Per-camera vignetting: the brightness left at vignetting_angle_deg off the optical axis,
  // uniform in [vignetting_min, vignetting_max] (1 1: none), falling with the squared angle.
  double vignetting_min = 1.0;
  double vignetting_max = 1.0;
  double vignetting_angle_deg = 110.0;
  double noise_sigma = 0.0;  // Gaussian sensor noise, 8-bit levels, drawn anew every frame

  // The ranges the robustness targets are measured with (docs/accuracy.md): gains 0.75-1.25,
  // casts of +-6 %, 45-65 % brightness at 110 degrees; no noise.
  static PhotometricOptions realistic();
  bool any() const {
    return gain_spread > 0 || color_cast > 0 || vignetting_min < 1 || vignetting_max < 1 ||
           noise_sigma > 0;
  }
  // Throws std::invalid_argument naming the field, its value and what is allowed.
  void check() const;
};

// One camera's response, drawn from `seed` and the camera index.
struct CameraResponse {
  double gain[3] = {1, 1, 1};  // gain times cast, per channel
  double vignetting = 1.0;     // brightness left at the options' angle
};
CameraResponse draw_camera_response(const PhotometricOptions& options, std::uint64_t seed,
                                    int camera);

// Rewrites `image` of `camera` as `radiance` (its colour in [0, 1], same size) through `response`
// and noise (seeded by `noise_seed`), rounded once; leaves `image` as it is where `options` has
// no effect. Throws std::invalid_argument when the two differ in size.
void apply_camera_response(const PhotometricOptions& options, const CameraResponse& response,
                           const RigCamera& camera, std::uint64_t noise_seed,
                           const RgbFloatImage& radiance, Rgb8Image* image);

}  // namespace omnisweep::synthetic
