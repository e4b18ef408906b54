// What every camera model shares: the pixel convention, parameter checks and rescaling.
//
// Conventions (ALGORITHM.md §1): camera frame x right, y down, z forward; pixel (0, 0) is the
// centre of the top-left pixel. Every model's first four parameters are fx, fy, cx, cy.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <optional>
#include <string>

namespace omnisweep {

// The first parameter a model rejects, with the reason (for error messages naming the field).
struct ParamIssue {
  int index = 0;
  std::string problem;
};

namespace camera_detail {

// Pixel-centre rescaling (ALGORITHM.md §1): f -> f * s, c -> (c + 0.5) * s - 0.5.
template <typename Params>
Params scale_intrinsics(Params p, typename Params::Scalar sx, typename Params::Scalar sy) {
  using S = typename Params::Scalar;
  p[0] *= sx;
  p[1] *= sy;
  p[2] = (p[2] + S(0.5)) * sx - S(0.5);
  p[3] = (p[3] + S(0.5)) * sy - S(0.5);
  return p;
}

// Checks shared by all models: finite values, positive focal lengths.
template <typename Params>
std::optional<ParamIssue> check_common(const Params& p) {
  for (int i = 0; i < p.size(); ++i) {
    if (!std::isfinite(double(p[i]))) return ParamIssue{i, "is not a finite number"};
  }
  if (!(p[0] > 0)) return ParamIssue{0, "must be > 0"};
  if (!(p[1] > 0)) return ParamIssue{1, "must be > 0"};
  return std::nullopt;
}

// The largest angle t in (0, limit] up to which the image radius of a ray at angle t from the
// optical axis keeps increasing. Past it the projection folds (two rays share a pixel), which
// happens for some parameters inside a model's nominal valid set (e.g. double sphere with
// xi = -0.5, alpha = 0.9). Sampled every limit / 4096, stopping at the last increasing sample.
template <typename Scalar, typename Radius>
Scalar monotonic_angle_limit(Radius radius, Scalar limit) {
  constexpr int kSteps = 4096;
  Scalar prev_t = 0;
  Scalar prev_r = radius(Scalar(0));
  for (int i = 1; i <= kSteps; ++i) {
    const Scalar t = limit * Scalar(i) / Scalar(kSteps);
    const Scalar r = radius(t);
    if (!(r > prev_r)) return prev_t;
    prev_t = t;
    prev_r = r;
  }
  return limit;
}

// Whether a point lies inside the cone of half-angle max_angle around +z (cos_max = its cosine).
template <typename Vec3, typename Scalar>
bool within_cone(const Vec3& p, Scalar cos_max) {
  const Scalar n = p.norm();
  return n > Scalar(0) && std::isfinite(n) && p.z() > cos_max * n;
}

}  // namespace camera_detail
}  // namespace omnisweep
