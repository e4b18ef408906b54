// Pinhole camera without distortion, basalt's "pinhole": u = fx x / z + cx, v = fy y / z + cy,
// valid for z > 0. Used for teleoperation and VR views rendered from the panorama.
#pragma once

#include <array>
#include <numbers>
#include <string_view>

#include "omnisweep/camera/camera_common.h"

namespace omnisweep {

template <typename Scalar = double>
class PinholeCamera : public CameraModelBase<PinholeCamera, Scalar, 4> {
  using Base = CameraModelBase<PinholeCamera, Scalar, 4>;

 public:
  static constexpr std::string_view kName = "pinhole";
  static constexpr std::array<std::string_view, 4> kParamNames = {"fx", "fy", "cx", "cy"};
  using typename Base::Params;
  using typename Base::Vec2;
  using typename Base::Vec3;

  PinholeCamera() : PinholeCamera(Params(1, 1, 0, 0)) {}
  explicit PinholeCamera(const Params& params) : Base(params) {
    this->set_valid_cone(std::numbers::pi_v<Scalar> / 2, [](Scalar t) { return t; });
  }

  bool project(const Vec3& p, Vec2* uv) const {
    if (!(p.z() > Scalar(0))) {
      this->to_pixel(Scalar(0), Scalar(0), uv);
      return false;
    }
    return this->to_pixel(p.x() / p.z(), p.y() / p.z(), uv) && p.allFinite();
  }

  bool unproject(const Vec2& uv, Vec3* ray) const {
    const Vec2 m = this->normalized(uv);
    if (!m.allFinite()) return false;
    *ray = Vec3(m.x(), m.y(), Scalar(1)).normalized();
    return true;
  }

  std::optional<ParamIssue> check() const { return this->check_common(); }
};

}  // namespace omnisweep
