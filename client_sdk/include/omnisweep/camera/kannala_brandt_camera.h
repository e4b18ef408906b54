// Kannala-Brandt equidistant fisheye model with four coefficients, basalt's "kb4".
//
// Parameters: fx, fy, cx, cy, k1, k2, k3, k4. Projection of (x, y, z):
//   r = |(x, y)|, theta = atan2(r, z), d(theta) = theta (1 + k1 theta^2 + ... + k4 theta^8)
//   u = fx * d * x / r + cx, v = fy * d * y / r + cy
// valid while d is increasing: theta below the first angle in (0, pi] where d stops growing (pi
// when it never does). Unprojection solves d(theta) = |(mx, my)| by Newton's method.
#pragma once

#include <array>
#include <cmath>
#include <numbers>
#include <string_view>

#include "omnisweep/camera/camera_common.h"

namespace omnisweep {

template <typename Scalar = double>
class KannalaBrandtCamera : public CameraModelBase<KannalaBrandtCamera, Scalar, 8> {
  using Base = CameraModelBase<KannalaBrandtCamera, Scalar, 8>;

 public:
  static constexpr std::string_view kName = "kb4";
  static constexpr std::array<std::string_view, 8> kParamNames = {"fx", "fy", "cx", "cy",
                                                                  "k1", "k2", "k3", "k4"};
  using typename Base::Params;
  using typename Base::Vec2;
  using typename Base::Vec3;

  KannalaBrandtCamera() : KannalaBrandtCamera((Params() << 1, 1, 0, 0, 0, 0, 0, 0).finished()) {}
  explicit KannalaBrandtCamera(const Params& params) : Base(params) {
    this->set_valid_cone(std::numbers::pi_v<Scalar>, [&](Scalar t) { return distort(t); });
  }

  bool project(const Vec3& p, Vec2* uv) const {
    const Scalar r = std::sqrt(p.x() * p.x() + p.y() * p.y());
    const Scalar d = distort(std::atan2(r, p.z()));
    // d / r tends to 1 / z on the optical axis.
    const Scalar scale = r > Scalar(1e-9) * std::abs(p.z()) ? d / r : Scalar(1) / p.z();
    return this->to_pixel(scale * p.x(), scale * p.y(), uv) && this->in_valid_cone(p);
  }

  bool unproject(const Vec2& uv, Vec3* ray) const {
    const Vec2 m = this->normalized(uv);
    const Scalar ru = m.norm();
    const Scalar theta_max = this->max_angle();
    if (!std::isfinite(ru) || ru > distort(theta_max)) return false;
    Scalar theta = ru < Scalar(1) ? ru : Scalar(1);
    for (int i = 0; i < 30; ++i) {  // Newton on the increasing d(theta) = ru
      const Scalar step = (distort(theta) - ru) / distort_derivative(theta);
      theta = std::clamp(theta - step, Scalar(0), theta_max);
      if (std::abs(step) < Scalar(1e-14)) break;
    }
    if (!(std::abs(distort(theta) - ru) <= Scalar(1e-6) * (Scalar(1) + ru))) return false;
    const Scalar s = std::sin(theta);
    const Vec3 r =
        ru > Scalar(0) ? Vec3(s * m.x() / ru, s * m.y() / ru, std::cos(theta)) : Vec3(0, 0, 1);
    if (theta >= theta_max && !this->in_valid_cone(r)) return false;
    *ray = r;
    return true;
  }

  std::optional<ParamIssue> check() const { return this->check_common(); }

 private:
  Scalar distort(Scalar t) const {
    const auto& k = this->params_;
    const Scalar t2 = t * t;
    return t * (Scalar(1) + t2 * (k[4] + t2 * (k[5] + t2 * (k[6] + t2 * k[7]))));
  }
  Scalar distort_derivative(Scalar t) const {
    const auto& k = this->params_;
    const Scalar t2 = t * t;
    return Scalar(1) +
           t2 * (Scalar(3) * k[4] +
                 t2 * (Scalar(5) * k[5] + t2 * (Scalar(7) * k[6] + t2 * Scalar(9) * k[7])));
  }
};

}  // namespace omnisweep
