#include "server/synthetic/procedural_texture.h"

#include <algorithm>
#include <cmath>

namespace omnisweep::synthetic {
namespace {

std::uint32_t hash3(std::int32_t x, std::int32_t y, std::int32_t z, std::uint32_t seed) {
  // A small integer hash (lowbias32 style mixing); any fixed mix works, it must be deterministic.
  std::uint32_t h = seed * 0x9E3779B9u;
  for (std::uint32_t v : {std::uint32_t(x), std::uint32_t(y), std::uint32_t(z)}) {
    h ^= v + 0x7F4A7C15u + (h << 6) + (h >> 2);
    h ^= h >> 16;
    h *= 0x7FEB352Du;
    h ^= h >> 15;
    h *= 0x846CA68Bu;
    h ^= h >> 16;
  }
  return h;
}

// Amplitude ratio between octaves: high enough that fine detail stays visible for matching.
constexpr float kGain = 0.72f;

float unit(std::uint32_t h) { return float(h >> 8) * (1.0f / 16777216.0f); }
float fade(float t) { return t * t * t * (t * (t * 6.0f - 15.0f) + 10.0f); }
float lerp(float a, float b, float t) { return a + (b - a) * t; }
float smoothstep(float e0, float e1, float x) {
  const float t = std::clamp((x - e0) / (e1 - e0), 0.0f, 1.0f);
  return t * t * (3.0f - 2.0f * t);
}

// 1 where detail of this wavelength is resolved (>= 4 footprints), 0 below 2 footprints.
float detail_weight(float wavelength, float footprint) {
  return std::clamp(wavelength / std::max(footprint, 1e-6f) * 0.5f - 1.0f, 0.0f, 1.0f);
}

Eigen::Vector3f mix(const Eigen::Vector3f& a, const Eigen::Vector3f& b, float t) {
  return a + (b - a) * t;
}

// Two coordinates along the surface: the axes other than the normal's dominant one.
Eigen::Vector2f surface_coords(const Eigen::Vector3f& p, const Eigen::Vector3f& n) {
  const Eigen::Vector3f a = n.cwiseAbs();
  if (a.x() >= a.y() && a.x() >= a.z()) return {p.z(), p.y()};
  if (a.y() >= a.z()) return {p.x(), p.z()};
  return {p.x(), p.y()};
}

// Contrast curve that keeps noise from averaging into flat grey.
float contrast(float v) { return smoothstep(0.2f, 0.8f, v); }

Eigen::Vector3f tiles(const Material& m, const Eigen::Vector3f& p, const Eigen::Vector3f& n,
                      float footprint) {
  const Eigen::Vector2f uv = surface_coords(p, n) / m.scale;
  const float fx = std::floor(uv.x()), fy = std::floor(uv.y());
  // Per-tile tone, resolved only while tiles are larger than a few pixels.
  const float tile_weight = detail_weight(m.scale, footprint);
  const float tone =
      lerp(0.5f, unit(hash3(std::int32_t(fx), std::int32_t(fy), 7, m.seed)), tile_weight);
  Eigen::Vector3f c = mix(m.color_a, m.color_b, 0.35f * tone);
  // Fine grain on each tile.
  const float grain = filtered_fbm(p, m.scale * 0.35f, footprint, m.seed + 11, 5);
  c *= 0.8f + 0.4f * grain;
  // Mortar lines, box-filtered over the footprint (in tile units).
  const float half_width = 0.03f;
  const float fp = footprint / m.scale;
  const float du = std::min(uv.x() - fx, 1.0f - (uv.x() - fx));
  const float dv = std::min(uv.y() - fy, 1.0f - (uv.y() - fy));
  auto coverage = [&](float d) {
    if (fp > 0.5f) return 2.0f * half_width;  // lines finer than the pixel: their mean
    return smoothstep(half_width + fp * 0.5f, half_width - fp * 0.5f, d);
  };
  const float line = std::max(coverage(du), coverage(dv));
  return mix(c, m.color_b * 0.35f, line);
}

}  // namespace

float value_noise(const Eigen::Vector3f& p, std::uint32_t seed) {
  const float fx = std::floor(p.x()), fy = std::floor(p.y()), fz = std::floor(p.z());
  const auto ix = std::int32_t(fx), iy = std::int32_t(fy), iz = std::int32_t(fz);
  const float tx = fade(p.x() - fx), ty = fade(p.y() - fy), tz = fade(p.z() - fz);
  float c[2][2][2];
  for (int dz = 0; dz < 2; ++dz)
    for (int dy = 0; dy < 2; ++dy)
      for (int dx = 0; dx < 2; ++dx) c[dz][dy][dx] = unit(hash3(ix + dx, iy + dy, iz + dz, seed));
  const float x00 = lerp(c[0][0][0], c[0][0][1], tx), x01 = lerp(c[0][1][0], c[0][1][1], tx);
  const float x10 = lerp(c[1][0][0], c[1][0][1], tx), x11 = lerp(c[1][1][0], c[1][1][1], tx);
  return lerp(lerp(x00, x01, ty), lerp(x10, x11, ty), tz);
}

float filtered_fbm(const Eigen::Vector3f& p, float wavelength, float footprint, std::uint32_t seed,
                   int octaves) {
  float sum = 0.0f, norm = 0.0f, amplitude = 1.0f;
  for (int k = 0; k < octaves; ++k) {
    const float w = detail_weight(wavelength, footprint);
    if (w <= 0.0f) {  // every finer octave is unresolved too: they add their mean
      for (; k < octaves; ++k, amplitude *= kGain) {
        sum += amplitude * 0.5f;
        norm += amplitude;
      }
      break;
    }
    // Offset each octave so lattice points do not line up across octaves.
    const Eigen::Vector3f q = p / wavelength + Eigen::Vector3f(0.37f, 0.71f, 0.13f) * float(k * 17);
    sum += amplitude * lerp(0.5f, value_noise(q, seed + std::uint32_t(k)), w);
    norm += amplitude;
    amplitude *= kGain;
    wavelength *= 0.5f;
  }
  return sum / norm;
}

Eigen::Vector3f albedo(const Material& m, const Eigen::Vector3f& p, const Eigen::Vector3f& n,
                       float footprint) {
  switch (m.pattern) {
    case Pattern::kPlain:
      return m.color_a;
    case Pattern::kNoise:
      return mix(m.color_a, m.color_b, contrast(filtered_fbm(p, m.scale, footprint, m.seed)));
    case Pattern::kTiles:
      return tiles(m, p, n, footprint);
    case Pattern::kStripes: {
      const float warp = filtered_fbm(p, m.scale * 2.0f, footprint, m.seed, 4) * 1.5f;
      const float band =
          0.5f + 0.5f * std::sin((p.y() + p.x() * 0.3f) / m.scale * 6.2831853f + warp * 6.0f);
      const float w = detail_weight(m.scale, footprint);
      const float detail = filtered_fbm(p, m.scale * 0.25f, footprint, m.seed + 5, 4);
      return mix(m.color_a, m.color_b, lerp(0.5f, band, w)) * (0.85f + 0.3f * detail);
    }
    case Pattern::kBlotches: {
      // Large regions (about 3 scales across): plain color_a, or noise between a and b.
      const float region = value_noise(p / (m.scale * 3.0f), m.seed + 101);
      const float textured = smoothstep(0.45f, 0.55f, region);
      const float noise = contrast(filtered_fbm(p, m.scale * 0.5f, footprint, m.seed));
      return mix(m.color_a, mix(m.color_a, m.color_b, noise), textured);
    }
  }
  return m.color_a;
}

}  // namespace omnisweep::synthetic
