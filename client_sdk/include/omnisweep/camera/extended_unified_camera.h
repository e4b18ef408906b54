// Extended unified camera model (Khomutenko et al. 2016), basalt's "eucm".
//
// Parameters: fx, fy, cx, cy, alpha, beta. Projection of (x, y, z):
//   d = sqrt(beta (x^2 + y^2) + z^2), den = alpha d + (1 - alpha) z
//   u = fx x / den + cx, v = fy y / den + cy
//   valid iff z > -w d, w = alpha > 0.5 ? (1 - alpha) / alpha : alpha / (1 - alpha)
// Unprojection: mx, my, r2 as for the double sphere model, valid iff alpha <= 0.5 or
//   r2 <= 1 / (beta (2 alpha - 1)); mz = (1 - beta alpha^2 r2) /
//   (alpha sqrt(1 - (2 alpha - 1) beta r2) + 1 - alpha), ray = normalise(mx, my, mz).
#pragma once

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <string_view>

#include "omnisweep/camera/camera_common.h"

namespace omnisweep {

template <typename Scalar = double>
class ExtendedUnifiedCamera {
 public:
  static constexpr int kNumParams = 6;
  static constexpr std::string_view kName = "eucm";
  static constexpr std::array<std::string_view, kNumParams> kParamNames = {"fx", "fy",    "cx",
                                                                           "cy", "alpha", "beta"};
  using Params = Eigen::Matrix<Scalar, kNumParams, 1>;
  using Vec2 = Eigen::Matrix<Scalar, 2, 1>;
  using Vec3 = Eigen::Matrix<Scalar, 3, 1>;

  ExtendedUnifiedCamera() : ExtendedUnifiedCamera(Params(1, 1, 0, 0, 0.5, 1)) {}
  explicit ExtendedUnifiedCamera(const Params& params)
      : params_(params), max_angle_(find_max_angle()) {
    cos_max_ = std::cos(max_angle_);
  }

  const Params& params() const { return params_; }
  Scalar alpha() const { return params_[4]; }
  Scalar beta() const { return params_[5]; }

  bool project(const Vec3& p, Vec2* uv) const {
    const Scalar x = p.x(), y = p.y(), z = p.z();
    const Scalar d = std::sqrt(beta() * (x * x + y * y) + z * z);
    const Scalar den = alpha() * d + (Scalar(1) - alpha()) * z;
    if (!(den > Scalar(0)) || !std::isfinite(den)) {
      *uv = Vec2(params_[2], params_[3]);
      return false;
    }
    *uv = Vec2(params_[0] * x / den + params_[2], params_[1] * y / den + params_[3]);
    return camera_detail::within_cone(p, cos_max_) && uv->allFinite();
  }

  bool unproject(const Vec2& uv, Vec3* ray) const {
    const Scalar mx = (uv.x() - params_[2]) / params_[0];
    const Scalar my = (uv.y() - params_[3]) / params_[1];
    const Scalar r2 = mx * mx + my * my;
    const Scalar a = alpha(), b = beta();
    const Scalar s = Scalar(1) - (Scalar(2) * a - Scalar(1)) * b * r2;
    if (!(s >= Scalar(0))) return false;
    const Scalar mz = (Scalar(1) - b * a * a * r2) / (a * std::sqrt(s) + Scalar(1) - a);
    const Vec3 r(mx, my, mz);
    const Scalar n = r.norm();
    if (!(n > Scalar(0)) || !std::isfinite(n)) return false;
    const Vec3 unit = r / n;
    // The ray must lie where projection is valid, so that the two stay inverse.
    if (!(unit.z() > cos_max_)) return false;
    *ray = unit;
    return true;
  }

  Scalar max_angle() const { return max_angle_; }

  ExtendedUnifiedCamera scaled(Scalar sx, Scalar sy) const {
    return ExtendedUnifiedCamera(camera_detail::scale_intrinsics(params_, sx, sy));
  }

  std::optional<ParamIssue> check() const {
    if (auto issue = camera_detail::check_common(params_)) return issue;
    if (!(alpha() >= 0 && alpha() <= 1)) return ParamIssue{4, "must be within [0, 1]"};
    if (!(beta() > 0)) return ParamIssue{5, "must be > 0"};
    return std::nullopt;
  }

  template <typename Other>
  ExtendedUnifiedCamera<Other> cast() const {
    return ExtendedUnifiedCamera<Other>(params_.template cast<Other>());
  }

 private:
  Scalar w() const {
    const Scalar a = alpha();
    return a > Scalar(0.5) ? (Scalar(1) - a) / a : a / (Scalar(1) - a);
  }

  // Largest angle to the optical axis with z > -w d, or the fold angle when that comes first.
  Scalar find_max_angle() const {
    // z = cos t, lateral = sin t: cos t > -w sqrt(beta sin^2 t + cos^2 t); solve at equality.
    const Scalar ww = w() * w();
    const Scalar c2 = ww * beta() / (Scalar(1) - ww + ww * beta());  // cos^2 t at the boundary
    const Scalar limit =
        std::acos(-std::sqrt(c2 < Scalar(0) ? Scalar(0) : (c2 > Scalar(1) ? Scalar(1) : c2)));
    const Scalar a = alpha(), b = beta();
    auto radius = [&](Scalar t) {
      const Scalar s = std::sin(t), c = std::cos(t);
      const Scalar den = a * std::sqrt(b * s * s + c * c) + (Scalar(1) - a) * c;
      return den > Scalar(0) ? s / den : Scalar(-1);
    };
    return limit == limit ? camera_detail::monotonic_angle_limit(radius, limit) : Scalar(0);
  }

  Params params_;
  Scalar max_angle_;
  Scalar cos_max_ = 1;
};

}  // namespace omnisweep
