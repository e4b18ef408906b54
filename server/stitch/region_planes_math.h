// The region planes' arithmetic (region_planes.h), in float as the kernels do it
// (shaders/include/region_planes.glsl holds the same functions in GLSL: keep the two in step).
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

#include "server/stitch/panorama_rays.h"

namespace omnisweep::stitch::region_math {

// A support block counts for at most this many regions (the first found).
constexpr int kNearRegions = 8;

struct Vec3f {
  float x = 0, y = 0, z = 0;
  float operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
  Vec3f operator+(const Vec3f& o) const { return {x + o.x, y + o.y, z + o.z}; }
  Vec3f operator*(float s) const { return {x * s, y * s, z * s}; }
};

inline float dot(const Vec3f& a, const Vec3f& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Vec3f cross(const Vec3f& a, const Vec3f& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

// The panorama's unit rays from panorama_ray_table, as the kernels compute them.
class Rays {
 public:
  Rays(int width, int height) : width_(width), table_(panorama_ray_table(width, height)) {}
  Vec3f operator()(int x, int y) const {
    const float* col = &table_[2 * std::size_t(x)];
    const float* row = &table_[2 * (std::size_t(width_) + y)];
    return {row[0] * col[0], row[0] * col[1], row[1]};
  }

 private:
  int width_;
  std::vector<float> table_;
};

// The PCG hash (Jarzynski and Olano, "Hash Functions for GPU Rendering", 2020): the draws and
// the support's sampling, reproducible and free of state.
inline std::uint32_t mix(std::uint32_t x) {
  const std::uint32_t state = x * 747796405u + 2891336453u;
  const std::uint32_t word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
  return (word >> 22u) ^ word;
}

// The t-th index drawn for the region whose first block is `root`, for its k-th plane.
inline std::uint32_t draw(std::uint32_t root, std::uint32_t k, std::uint32_t t) {
  return mix(root * 0x9e3779b9u ^ mix(k * 0x85ebca6bu ^ mix(t)));
}

// The hash a support block is sampled by, for the region whose first block is `root`.
inline std::uint32_t support_hash(std::uint32_t block, std::uint32_t root) {
  return mix(block * 0x9e3779b9u ^ mix(root + 0x7f4a7c15u));
}

// The last of the 256 bins whose supports together are at most `capacity`; -1 if the first
// alone is more.
inline int last_bin(const std::array<std::uint32_t, 256>& bins, int capacity) {
  std::uint32_t sum = 0;
  int last = -1;
  for (int t = 0; t < 256; ++t) {
    if (sum + bins[t] > std::uint32_t(capacity)) break;
    sum += bins[t];
    last = t;
  }
  return last;
}

// Inliers a plane needs in a sample of n of `supports` supports.
inline int needed_inliers(int n, std::uint32_t supports, int min_inliers, int fraction) {
  const auto share = int((std::uint64_t(min_inliers) * std::uint64_t(n) + supports - 1) / supports);
  return std::max({3, share, n / fraction});
}

// The a of a . r_i = v_i (i = 0, 1, 2) by Cramer's rule; false where |det| <= min_det or the
// result is not finite.
inline bool solve(const Vec3f& r0, const Vec3f& r1, const Vec3f& r2, const Vec3f& v, float min_det,
                  Vec3f& a) {
  const Vec3f c12 = cross(r1, r2), c20 = cross(r2, r0), c01 = cross(r0, r1);
  const float det = dot(r0, c12);
  if (!(std::abs(det) > min_det)) return false;
  const float inv = 1.0f / det;
  a = (c12 * v.x + c20 * v.y + c01 * v.z) * inv;
  return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z);
}

// A support's MSAC score for the plane a: 1 - (residual / tau v)^2 within the band, else 0.
inline float msac(const Vec3f& a, const Vec3f& r, float v, float tau) {
  const float e = (dot(a, r) - v) / (tau * v);
  return std::max(0.0f, 1.0f - e * e);
}

inline bool is_inlier(const Vec3f& a, const Vec3f& r, float v, float tau) {
  return std::abs(dot(a, r) - v) < tau * v;
}

// The cosine a support's ray must exceed with a block's centre ray to count for its surround
// (RegionPlaneParams::surround_angle_deg), in float as the kernels get it.
inline float surround_cos(double angle_deg) {
  return float(std::cos(angle_deg * std::numbers::pi / 180.0));
}

// The quadrant (a bit of 4) of the tangent plane at `centre` that the ray t lies in; 0 if t is
// not within the surround's angle of it (dot(t, centre) <= min_cos).
inline std::uint32_t quadrant(const Vec3f& centre, const Vec3f& t, float min_cos) {
  if (!(dot(t, centre) > min_cos)) return 0;
  Vec3f e1{-centre.y, centre.x, 0.0f};  // (0, 0, 1) x centre
  const float len = std::sqrt(dot(e1, e1));
  e1 = len < 1e-6f ? Vec3f{1.0f, 0.0f, 0.0f} : e1 * (1.0f / len);
  const Vec3f e2 = cross(centre, e1);
  const float u = dot(t, e1), w = dot(t, e2);
  return u >= 0.0f ? (w >= 0.0f ? 1u : 2u) : (w >= 0.0f ? 4u : 8u);
}

// The planes (bits) whose 4 quadrant bits in `quadrants` have at least 3 set.
inline std::uint32_t surrounding(std::uint64_t quadrants) {
  std::uint32_t mask = 0;
  for (int k = 0; k < 16; ++k)
    if (std::popcount(std::uint32_t(quadrants >> (4 * k)) & 15u) >= 3) mask |= 1u << k;
  return mask;
}

// A pixel's distance from the surrounding plane (of `mask`) nearest its own inverse distance,
// mixed with it by 1 - confidence / fill_below and clamped; false if no plane is in front.
inline bool apply(const Vec3f* planes, int count, std::uint32_t mask, const Vec3f& ray, float d,
                  float c, float fill_below, float v_min, float v_max, float& out) {
  const float own = 1.0f / d;
  float pick = 0.0f, nearest = INFINITY;
  for (int k = 0; k < count; ++k) {
    if (!(mask & (1u << k))) continue;
    const float pv = dot(planes[k], ray);
    if (pv > 0.0f && std::abs(pv - own) < nearest) {
      nearest = std::abs(pv - own);
      pick = pv;
    }
  }
  if (!(pick > 0.0f)) return false;
  const float alpha = 1.0f - c / fill_below;
  out = 1.0f / std::clamp(alpha * pick + (1.0f - alpha) * own, v_min, v_max);
  return true;
}

}  // namespace omnisweep::stitch::region_math
