#include "omnisweep/rig/rig.h"

#include <stdexcept>
#include <string>

namespace omnisweep {

RigCamera RigCamera::resized(int new_width, int new_height) const {
  RigCamera out = *this;
  out.model = model.scaled(double(new_width) / width, double(new_height) / height);
  out.width = new_width;
  out.height = new_height;
  return out;
}

Rigid3d Rig::cam_from_cam(int target, int source) const {
  return cameras.at(target).rig_from_cam.inverse() * cameras.at(source).rig_from_cam;
}

Rig Rig::resized(int width, int height) const {
  Rig out;
  for (const RigCamera& cam : cameras) out.cameras.push_back(cam.resized(width, height));
  return out;
}

void Rig::check() const {
  if (cameras.size() < 2) {
    throw std::invalid_argument("a rig needs at least 2 cameras, found " +
                                std::to_string(cameras.size()));
  }
  for (std::size_t c = 0; c < cameras.size(); ++c) {
    const RigCamera& cam = cameras[c];
    const std::string where = "camera " + std::to_string(c) + ": ";
    if (cam.width <= 0 || cam.height <= 0) {
      throw std::invalid_argument(where + "resolution " + std::to_string(cam.width) + "x" +
                                  std::to_string(cam.height) + " must be positive");
    }
    if (auto issue = cam.model.check()) {
      throw std::invalid_argument(where + std::string(cam.model.param_names()[issue->index]) + " " +
                                  issue->problem);
    }
    if (!cam.rig_from_cam.translation.allFinite() ||
        !cam.rig_from_cam.rotation.coeffs().allFinite() ||
        std::abs(cam.rig_from_cam.rotation.norm() - 1.0) > 1e-6) {
      throw std::invalid_argument(where + "pose must be finite with a unit quaternion");
    }
  }
}

}  // namespace omnisweep
