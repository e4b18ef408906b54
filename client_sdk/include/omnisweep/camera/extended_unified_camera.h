// Extended unified camera model (Khomutenko et al. 2016), basalt's "eucm".
//
// Parameters: fx, fy, cx, cy, alpha, beta. Projection of (x, y, z):
//   d = sqrt(beta (x^2 + y^2) + z^2), den = alpha d + (1 - alpha) z
//   u = fx x / den + cx, v = fy y / den + cy
//   valid iff z > -w d, w = alpha > 0.5 ? (1 - alpha) / alpha : alpha / (1 - alpha)
// Unprojection: mx, my, r2 as for the double sphere model, valid iff alpha <= 0.5 or
//   r2 <= 1 / (beta (2 alpha - 1)); mz = (1 - beta alpha^2 r2) /
//   (alpha sqrt(1 - (2 alpha - 1) beta r2) + 1 - alpha), ray = normalise(mx, my, mz).
// As for the double sphere model, the valid cone ends where the projection would fold.
#pragma once

#include <array>
#include <cmath>
#include <string_view>

#include "omnisweep/camera/camera_common.h"

namespace omnisweep {

template <typename Scalar = double>
class ExtendedUnifiedCamera : public CameraModelBase<ExtendedUnifiedCamera, Scalar, 6> {
  using Base = CameraModelBase<ExtendedUnifiedCamera, Scalar, 6>;

 public:
  static constexpr std::string_view kName = "eucm";
  static constexpr std::array<std::string_view, 6> kParamNames = {"fx", "fy",    "cx",
                                                                  "cy", "alpha", "beta"};
  using typename Base::Params;
  using typename Base::Vec2;
  using typename Base::Vec3;

  ExtendedUnifiedCamera() : ExtendedUnifiedCamera(Params(1, 1, 0, 0, 0.5, 1)) {}
  explicit ExtendedUnifiedCamera(const Params& params) : Base(params) {
    // Boundary z = -w d with z = cos t, lateral = sin t: cos^2 t = w^2 beta / (1 - w^2 + w^2 beta).
    const Scalar a = alpha(), b = beta();
    const Scalar w = a > Scalar(0.5) ? (Scalar(1) - a) / a : a / (Scalar(1) - a);
    const Scalar c2 = w * w * b / (Scalar(1) - w * w + w * w * b);
    const Scalar limit = camera_detail::clamped_acos(-std::sqrt(c2 < Scalar(0) ? Scalar(0) : c2));
    this->set_valid_cone(limit, [&](Scalar t) {
      const Scalar s = std::sin(t), c = std::cos(t);
      const Scalar den = a * std::sqrt(b * s * s + c * c) + (Scalar(1) - a) * c;
      return den > Scalar(0) ? s / den : Scalar(-1);
    });
  }

  Scalar alpha() const { return this->params_[4]; }
  Scalar beta() const { return this->params_[5]; }

  bool project(const Vec3& p, Vec2* uv) const {
    const Scalar x = p.x(), y = p.y(), z = p.z();
    const Scalar d = std::sqrt(beta() * (x * x + y * y) + z * z);
    const Scalar den = alpha() * d + (Scalar(1) - alpha()) * z;
    if (!(den > Scalar(0)) || !std::isfinite(den)) {
      this->to_pixel(Scalar(0), Scalar(0), uv);
      return false;
    }
    return this->to_pixel(x / den, y / den, uv) && this->in_valid_cone(p);
  }

  bool unproject(const Vec2& uv, Vec3* ray) const {
    const Vec2 m = this->normalized(uv);
    const Scalar r2 = m.squaredNorm();
    const Scalar a = alpha(), b = beta();
    const Scalar s = Scalar(1) - (Scalar(2) * a - Scalar(1)) * b * r2;
    if (!(s >= Scalar(0))) return false;
    const Scalar mz = (Scalar(1) - b * a * a * r2) / (a * std::sqrt(s) + Scalar(1) - a);
    const Vec3 r(m.x(), m.y(), mz);
    if (!this->in_valid_cone(r)) return false;
    *ray = r.normalized();
    return true;
  }

  std::optional<ParamIssue> check() const {
    if (auto issue = this->check_common()) return issue;
    if (!(alpha() >= 0 && alpha() <= 1)) return ParamIssue{4, "must be within [0, 1]"};
    if (!(beta() > 0)) return ParamIssue{5, "must be > 0"};
    return std::nullopt;
  }
};

}  // namespace omnisweep
