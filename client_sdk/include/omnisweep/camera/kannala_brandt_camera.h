// Kannala-Brandt equidistant fisheye model with four coefficients, basalt's "kb4".
//
// Parameters: fx, fy, cx, cy, k1, k2, k3, k4. Projection of (x, y, z):
//   r = |(x, y)|, theta = atan2(r, z), d(theta) = theta (1 + k1 theta^2 + ... + k4 theta^8)
//   u = fx * d * x / r + cx, v = fy * d * y / r + cy
// valid while d is increasing: theta <= theta_max, the first root of d'(theta) in (0, pi]
// (pi when there is none). Unprojection solves d(theta) = |(mx, my)| by Newton's method.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <numbers>
#include <string_view>

#include "omnisweep/camera/camera_common.h"

namespace omnisweep {

template <typename Scalar = double>
class KannalaBrandtCamera {
 public:
  static constexpr int kNumParams = 8;
  static constexpr std::string_view kName = "kb4";
  static constexpr std::array<std::string_view, kNumParams> kParamNames = {"fx", "fy", "cx", "cy",
                                                                           "k1", "k2", "k3", "k4"};
  using Params = Eigen::Matrix<Scalar, kNumParams, 1>;
  using Vec2 = Eigen::Matrix<Scalar, 2, 1>;
  using Vec3 = Eigen::Matrix<Scalar, 3, 1>;

  KannalaBrandtCamera()
      : KannalaBrandtCamera(Params((Params() << 1, 1, 0, 0, 0, 0, 0, 0).finished())) {}
  explicit KannalaBrandtCamera(const Params& params)
      : params_(params), theta_max_(find_theta_max()) {}

  const Params& params() const { return params_; }

  bool project(const Vec3& p, Vec2* uv) const {
    const Scalar r = std::sqrt(p.x() * p.x() + p.y() * p.y());
    const Scalar theta = std::atan2(r, p.z());
    const Scalar d = distort(theta);
    // d / r tends to 1 / z on the optical axis.
    const Scalar scale = r > Scalar(1e-9) * std::abs(p.z()) ? d / r : Scalar(1) / p.z();
    Vec2 out(params_[0] * scale * p.x() + params_[2], params_[1] * scale * p.y() + params_[3]);
    if (!out.allFinite()) out = Vec2(params_[2], params_[3]);
    *uv = out;
    return p.allFinite() && p.norm() > Scalar(0) && theta <= theta_max_ && std::isfinite(scale);
  }

  bool unproject(const Vec2& uv, Vec3* ray) const {
    const Scalar mx = (uv.x() - params_[2]) / params_[0];
    const Scalar my = (uv.y() - params_[3]) / params_[1];
    const Scalar ru = std::sqrt(mx * mx + my * my);
    if (!std::isfinite(ru) || ru > distort(theta_max_)) return false;
    Scalar theta = ru < Scalar(1) ? ru : Scalar(1);
    for (int i = 0; i < 30; ++i) {  // Newton on the monotonic d(theta) = ru
      const Scalar step = (distort(theta) - ru) / distort_derivative(theta);
      theta -= step;
      theta = theta < Scalar(0) ? Scalar(0) : (theta > theta_max_ ? theta_max_ : theta);
      if (std::abs(step) < Scalar(1e-14)) break;
    }
    if (!(std::abs(distort(theta) - ru) <= Scalar(1e-6) * (Scalar(1) + ru))) return false;
    const Scalar s = std::sin(theta);
    *ray = ru > Scalar(0) ? Vec3(s * mx / ru, s * my / ru, std::cos(theta)) : Vec3(0, 0, 1);
    return true;
  }

  Scalar max_angle() const { return theta_max_; }

  KannalaBrandtCamera scaled(Scalar sx, Scalar sy) const {
    return KannalaBrandtCamera(camera_detail::scale_intrinsics(params_, sx, sy));
  }

  std::optional<ParamIssue> check() const { return camera_detail::check_common(params_); }

  template <typename Other>
  KannalaBrandtCamera<Other> cast() const {
    return KannalaBrandtCamera<Other>(params_.template cast<Other>());
  }

 private:
  Scalar distort(Scalar t) const {
    const Scalar t2 = t * t;
    return t * (Scalar(1) +
                t2 * (params_[4] + t2 * (params_[5] + t2 * (params_[6] + t2 * params_[7]))));
  }
  Scalar distort_derivative(Scalar t) const {
    const Scalar t2 = t * t;
    return Scalar(1) + t2 * (Scalar(3) * params_[4] +
                             t2 * (Scalar(5) * params_[5] +
                                   t2 * (Scalar(7) * params_[6] + t2 * Scalar(9) * params_[7])));
  }
  // Scans (0, pi] for the first point where d stops increasing, then bisects it.
  Scalar find_theta_max() const {
    const Scalar pi = std::numbers::pi_v<Scalar>;
    constexpr int kSteps = 1024;
    Scalar prev = 0;
    for (int i = 1; i <= kSteps; ++i) {
      const Scalar t = pi * Scalar(i) / Scalar(kSteps);
      if (!(distort_derivative(t) > Scalar(0))) {
        Scalar lo = prev, hi = t;
        for (int k = 0; k < 60; ++k) {
          const Scalar mid = (lo + hi) / 2;
          (distort_derivative(mid) > Scalar(0) ? lo : hi) = mid;
        }
        return lo;
      }
      prev = t;
    }
    return pi;
  }

  Params params_;
  Scalar theta_max_;
};

}  // namespace omnisweep
