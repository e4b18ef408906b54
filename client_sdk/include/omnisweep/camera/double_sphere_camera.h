// Double sphere camera model (Usenko, Demmel, Cremers, 3DV 2018), basalt's "ds".
//
// Parameters: fx, fy, cx, cy, xi, alpha. Projection of a point (x, y, z), ALGORITHM.md §2:
//   d1 = |(x, y, z)|, c = xi * d1 + z, d2 = |(x, y, c)|, den = alpha * d2 + (1 - alpha) * c
//   u = fx * x / den + cx, v = fy * y / den + cy
//   valid iff z > -w2 * d1, w1 = alpha > 0.5 ? (1 - alpha) / alpha : alpha / (1 - alpha),
//   w2 = (w1 + xi) / sqrt(2 * w1 * xi + xi^2 + 1)
// Unprojection of (u, v) to a unit ray:
//   mx = (u - cx) / fx, my = (v - cy) / fy, r2 = mx^2 + my^2, valid iff 1 - (2 alpha - 1) r2 >= 0
//   mz = (1 - alpha^2 r2) / (alpha * sqrt(1 - (2 alpha - 1) r2) + 1 - alpha)
//   k = (mz * xi + sqrt(mz^2 + (1 - xi^2) r2)) / (mz^2 + r2), ray = (k mx, k my, k mz - xi)
// For parameters where the projection folds before that limit (see monotonic_angle_limit), the
// valid cone ends at the fold. A pixel is valid when its ray lies in the valid cone, so that
// project and unproject are inverse on their valid sets, whatever the parameters.
#pragma once

#include <array>
#include <cmath>
#include <string_view>

#include "omnisweep/camera/camera_common.h"

namespace omnisweep {

template <typename Scalar = double>
class DoubleSphereCamera : public CameraModelBase<DoubleSphereCamera, Scalar, 6> {
  using Base = CameraModelBase<DoubleSphereCamera, Scalar, 6>;

 public:
  static constexpr std::string_view kName = "ds";
  static constexpr std::array<std::string_view, 6> kParamNames = {"fx", "fy", "cx",
                                                                  "cy", "xi", "alpha"};
  using typename Base::Params;
  using typename Base::Vec2;
  using typename Base::Vec3;

  DoubleSphereCamera() : DoubleSphereCamera(Params(1, 1, 0, 0, 0, 0.5)) {}
  explicit DoubleSphereCamera(const Params& params) : Base(params) {
    const Scalar a = alpha(), x = xi();
    this->set_valid_cone(camera_detail::clamped_acos(-w2()), [&](Scalar t) {
      const Scalar c = x + std::cos(t);
      const Scalar den = a * std::sqrt(std::sin(t) * std::sin(t) + c * c) + (Scalar(1) - a) * c;
      return den > Scalar(0) ? std::sin(t) / den : Scalar(-1);
    });
  }

  Scalar xi() const { return this->params_[4]; }
  Scalar alpha() const { return this->params_[5]; }

  // Returns true when p projects validly. *uv is written whenever the formula is defined
  // (also for some invalid points) and is never NaN.
  bool project(const Vec3& p, Vec2* uv) const {
    const Scalar x = p.x(), y = p.y(), z = p.z();
    const Scalar d1 = std::sqrt(x * x + y * y + z * z);
    const Scalar c = xi() * d1 + z;
    const Scalar d2 = std::sqrt(x * x + y * y + c * c);
    const Scalar den = alpha() * d2 + (Scalar(1) - alpha()) * c;
    if (!(den > Scalar(0)) || !std::isfinite(den)) {
      this->to_pixel(Scalar(0), Scalar(0), uv);
      return false;
    }
    return this->to_pixel(x / den, y / den, uv) && this->in_valid_cone(p);
  }

  // Returns true when (u, v) maps to a ray; *ray (unit length) is written only then.
  bool unproject(const Vec2& uv, Vec3* ray) const {
    const Vec2 m = this->normalized(uv);
    const Scalar r2 = m.squaredNorm();
    const Scalar a = alpha(), x = xi();
    const Scalar s1 = Scalar(1) - (Scalar(2) * a - Scalar(1)) * r2;
    if (!(s1 >= Scalar(0))) return false;
    const Scalar mz = (Scalar(1) - a * a * r2) / (a * std::sqrt(s1) + Scalar(1) - a);
    const Scalar s2 = mz * mz + (Scalar(1) - x * x) * r2;
    const Scalar den = mz * mz + r2;
    if (!(s2 >= Scalar(0)) || !(den > Scalar(0))) return false;
    const Scalar k = (mz * x + std::sqrt(s2)) / den;
    const Vec3 r(k * m.x(), k * m.y(), k * mz - x);
    if (!this->in_valid_cone(r)) return false;
    *ray = r.normalized();
    return true;
  }

  std::optional<ParamIssue> check() const {
    if (auto issue = this->check_common()) return issue;
    if (!(alpha() >= 0 && alpha() <= 1)) return ParamIssue{5, "must be within [0, 1]"};
    return std::nullopt;
  }

 private:
  Scalar w2() const {
    const Scalar a = alpha(), x = xi();
    const Scalar w1 = a > Scalar(0.5) ? (Scalar(1) - a) / a : a / (Scalar(1) - a);
    return (w1 + x) / std::sqrt(Scalar(2) * w1 * x + x * x + Scalar(1));
  }
};

}  // namespace omnisweep
