// Rig cameras packed for the shaders (struct Camera in shaders/include/camera.glsl, std430).
#pragma once

#include <cstdint>
#include <vector>

#include "omnisweep/rig/rig.h"

namespace omnisweep::depth {

struct GpuCamera {
  float focal_center[4];  // fx, fy, cx, cy
  float extra[4];         // model parameters after the first four
  float rows[3][4];       // cam_from_ref: rotation rows | translation
  std::uint32_t model;    // 0 ds, 1 kb4, 2 eucm, 3 pinhole
  float cos_max;
  std::uint32_t width;
  std::uint32_t height;
};
static_assert(sizeof(GpuCamera) == 96, "must match the std430 layout of struct Camera");

// Every camera of `rig` with its transform from camera `reference`'s frame.
std::vector<GpuCamera> pack_cameras(const Rig& rig, int reference);

}  // namespace omnisweep::depth
