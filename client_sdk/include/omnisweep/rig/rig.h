// A calibrated multi-camera rig: per camera a projection model, the image size it was
// calibrated at, and its pose rig_from_cam (x_in_rig = rig_from_cam * x_in_cam, ALGORITHM.md §1).
#pragma once

#include <vector>

#include "omnisweep/camera/camera_model.h"
#include "omnisweep/geometry/rigid3.h"

namespace omnisweep {

struct RigCamera {
  CameraModel<double> model;
  int width = 0;
  int height = 0;
  Rigid3d rig_from_cam;

  Eigen::Vector3d center_in_rig() const { return rig_from_cam.translation; }

  // The same camera for an image resized to new_width x new_height: intrinsics scale with the
  // pixel-centre convention of ALGORITHM.md §1, the pose is unchanged.
  RigCamera resized(int new_width, int new_height) const;
};

struct Rig {
  std::vector<RigCamera> cameras;

  int num_cameras() const { return static_cast<int>(cameras.size()); }
  // Takes points from camera `source` to camera `target`: T_target^-1 * T_source.
  Rigid3d cam_from_cam(int target, int source) const;
  // Every camera resized to width x height.
  Rig resized(int width, int height) const;
  // Throws std::invalid_argument naming the first problem (fewer than 2 cameras, bad sizes,
  // bad intrinsics). The calibration reader reports the same checks with file and field.
  void check() const;
};

}  // namespace omnisweep
