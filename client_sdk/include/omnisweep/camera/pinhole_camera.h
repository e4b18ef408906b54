// Pinhole camera without distortion, basalt's "pinhole": u = fx x / z + cx, v = fy y / z + cy,
// valid for z > 0. Used for teleoperation and VR views rendered from the panorama.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <numbers>
#include <string_view>

#include "omnisweep/camera/camera_common.h"

namespace omnisweep {

template <typename Scalar = double>
class PinholeCamera {
 public:
  static constexpr int kNumParams = 4;
  static constexpr std::string_view kName = "pinhole";
  static constexpr std::array<std::string_view, kNumParams> kParamNames = {"fx", "fy", "cx", "cy"};
  using Params = Eigen::Matrix<Scalar, kNumParams, 1>;
  using Vec2 = Eigen::Matrix<Scalar, 2, 1>;
  using Vec3 = Eigen::Matrix<Scalar, 3, 1>;

  PinholeCamera() : PinholeCamera(Params(1, 1, 0, 0)) {}
  explicit PinholeCamera(const Params& params) : params_(params) {}

  const Params& params() const { return params_; }

  bool project(const Vec3& p, Vec2* uv) const {
    if (!(p.z() > Scalar(0))) {
      *uv = Vec2(params_[2], params_[3]);
      return false;
    }
    *uv = Vec2(params_[0] * p.x() / p.z() + params_[2], params_[1] * p.y() / p.z() + params_[3]);
    if (!uv->allFinite()) {
      *uv = Vec2(params_[2], params_[3]);
      return false;
    }
    return p.allFinite();
  }

  bool unproject(const Vec2& uv, Vec3* ray) const {
    const Vec3 r((uv.x() - params_[2]) / params_[0], (uv.y() - params_[3]) / params_[1], 1);
    if (!r.allFinite()) return false;
    *ray = r.normalized();
    return true;
  }

  Scalar max_angle() const { return std::numbers::pi_v<Scalar> / 2; }

  PinholeCamera scaled(Scalar sx, Scalar sy) const {
    return PinholeCamera(camera_detail::scale_intrinsics(params_, sx, sy));
  }

  std::optional<ParamIssue> check() const { return camera_detail::check_common(params_); }

  template <typename Other>
  PinholeCamera<Other> cast() const {
    return PinholeCamera<Other>(params_.template cast<Other>());
  }

 private:
  Params params_;
};

}  // namespace omnisweep
