// Solid (3D) procedural textures for the synthetic rig. Every pattern takes the pixel's
// footprint on the surface (metres) and fades detail finer than about two footprints to its
// mean, so one ray per pixel gives anti-aliased images and the same surface point looks the
// same from cameras at different distances (which stereo matching relies on).
#pragma once

#include <Eigen/Core>
#include <cstdint>

namespace omnisweep::synthetic {

enum class Pattern : std::uint8_t {
  kPlain,     // one colour: the textureless areas stereo has to cope with
  kNoise,     // multi-octave value noise between two colours
  kTiles,     // tiles with per-tile colour and mortar lines (floors)
  kStripes,   // wavy bands
  kBlotches,  // large plain regions and noisy regions side by side (walls)
};

struct Material {
  Pattern pattern = Pattern::kPlain;
  Eigen::Vector3f color_a{0.5f, 0.5f, 0.5f};  // linear RGB in [0, 1]
  Eigen::Vector3f color_b{0.2f, 0.2f, 0.2f};
  float scale = 1.0f;  // metres: base noise wavelength, tile or band size
  std::uint32_t seed = 0;
};

// Albedo of `material` at `point` (world, metres) on a surface with `normal`, for a pixel
// footprint of `footprint` metres.
Eigen::Vector3f albedo(const Material& material, const Eigen::Vector3f& point,
                       const Eigen::Vector3f& normal, float footprint);

// Value noise in [0, 1] on the integer lattice, C2-smooth (quintic fade); deterministic.
float value_noise(const Eigen::Vector3f& p, std::uint32_t seed);
// Octaves of value noise from `wavelength` down, each faded out where finer than the footprint.
float filtered_fbm(const Eigen::Vector3f& p, float wavelength, float footprint, std::uint32_t seed,
                   int octaves = 7);

}  // namespace omnisweep::synthetic
