// What every camera model shares: parameter storage, rescaling with the pixel-centre
// convention, casting, parameter checks and the cone of valid rays.
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

template <typename Scalar>
Scalar clamped_acos(Scalar c) {
  return std::acos(c < Scalar(-1) ? Scalar(-1) : (c > Scalar(1) ? Scalar(1) : c));
}

}  // namespace camera_detail

// CRTP base of the models: Model<Scalar> derives from CameraModelBase<Model, Scalar, N>.
template <template <typename> class Model, typename Scalar, int N>
class CameraModelBase {
 public:
  static constexpr int kNumParams = N;
  using Params = Eigen::Matrix<Scalar, N, 1>;
  using Vec2 = Eigen::Matrix<Scalar, 2, 1>;
  using Vec3 = Eigen::Matrix<Scalar, 3, 1>;

  const Params& params() const { return params_; }
  // Largest angle between the optical axis and a valid ray (half the model's field of view).
  Scalar max_angle() const { return max_angle_; }

  // The same camera for an image resized by sx, sy (new / original): f -> f * s,
  // c -> (c + 0.5) * s - 0.5 (ALGORITHM.md §1).
  Model<Scalar> scaled(Scalar sx, Scalar sy) const {
    Params p = params_;
    p[0] *= sx;
    p[1] *= sy;
    p[2] = (p[2] + Scalar(0.5)) * sx - Scalar(0.5);
    p[3] = (p[3] + Scalar(0.5)) * sy - Scalar(0.5);
    return Model<Scalar>(p);
  }

  template <typename Other>
  Model<Other> cast() const {
    return Model<Other>(params_.template cast<Other>());
  }

 protected:
  explicit CameraModelBase(const Params& params) : params_(params) {}

  // Sets the valid cone to `limit`, or to the fold angle when `radius` (image radius / f of
  // the ray at angle t) stops increasing first.
  template <typename Radius>
  void set_valid_cone(Scalar limit, Radius radius) {
    max_angle_ =
        std::isnan(limit) ? Scalar(0) : camera_detail::monotonic_angle_limit(radius, limit);
    cos_max_ = std::cos(max_angle_);
  }

  // Whether a point lies strictly inside the valid cone (finite and non-zero).
  bool in_valid_cone(const Vec3& p) const {
    const Scalar n = p.norm();
    return n > Scalar(0) && std::isfinite(n) && p.z() > cos_max_ * n;
  }

  // Checks shared by all models: finite values, positive focal lengths.
  std::optional<ParamIssue> check_common() const {
    for (int i = 0; i < N; ++i) {
      if (!std::isfinite(double(params_[i]))) return ParamIssue{i, "is not a finite number"};
    }
    if (!(params_[0] > 0)) return ParamIssue{0, "must be > 0"};
    if (!(params_[1] > 0)) return ParamIssue{1, "must be > 0"};
    return std::nullopt;
  }

  // Normalised image coordinates of pixel uv.
  Vec2 normalized(const Vec2& uv) const {
    return {(uv.x() - params_[2]) / params_[0], (uv.y() - params_[3]) / params_[1]};
  }
  // Pixel of normalised coordinates (mx, my); the principal point when not finite.
  bool to_pixel(Scalar mx, Scalar my, Vec2* uv) const {
    *uv = Vec2(params_[0] * mx + params_[2], params_[1] * my + params_[3]);
    if (uv->allFinite()) return true;
    *uv = Vec2(params_[2], params_[3]);
    return false;
  }

  Params params_;
  Scalar max_angle_ = 0;
  Scalar cos_max_ = 1;
};

}  // namespace omnisweep
