// Cameras packed for the shaders (struct Camera in shaders/include/camera.glsl, std430): rig
// cameras of any model, and equirectangular panoramas (ALGORITHM.md §5 convention) as model 4.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "omnisweep/gpu/kernel.h"
#include "omnisweep/image/image.h"
#include "omnisweep/reproject/camera_model_ids.h"
#include "omnisweep/rig/rig.h"

namespace omnisweep::reproject {

// GpuCamera::model, as the kernels number the models (camera_model_ids.h).
enum class GpuModel : std::uint32_t {
  kDoubleSphere = OMNISWEEP_MODEL_DOUBLE_SPHERE,
  kKannalaBrandt = OMNISWEEP_MODEL_KANNALA_BRANDT,
  kExtendedUnified = OMNISWEEP_MODEL_EXTENDED_UNIFIED,
  kPinhole = OMNISWEEP_MODEL_PINHOLE,
  kEquirectangular = OMNISWEEP_MODEL_EQUIRECTANGULAR,
  kAny = OMNISWEEP_MODEL_ANY,  // a role whose cameras differ (model_constants)
};

struct GpuCamera {
  float focal_center[4];  // fx, fy, cx, cy
  float extra[4];         // model parameters after the first four
  float rows[3][4];       // cam_from_ref: rotation rows | translation
  std::uint32_t model;    // a GpuModel
  float cos_max;
  std::uint32_t width;
  std::uint32_t height;
};
static_assert(sizeof(GpuCamera) == 96, "must match the std430 layout of struct Camera");

// Camera records one kernel can read (its uniform buffer, shaders/include/camera.glsl).
inline constexpr std::size_t kMaxCameraRecords = 170;
// The camera binding of a kernel (a uniform buffer).
inline gpu::BindingSlot camera_binding() { return gpu::BindingSlot::uniform(); }
// Throws std::invalid_argument when `records` camera records exceed kMaxCameraRecords.
void check_camera_records(std::size_t records);

// RGB8 pixels as the shaders read them (pixels.glsl): one uint per pixel, r in the lowest
// byte, alpha 255. `out` must hold width x height values.
void pack_rgba8(Rgb8View rgb, std::span<std::uint32_t> out);

// Every camera of `rig` with its transform from camera `reference`'s frame.
std::vector<GpuCamera> pack_cameras(const Rig& rig, int reference);

// One camera: `model` at width x height, whose frame is reached from the frame of reference by
// cam_from_ref.
GpuCamera pack_camera(const CameraModel<double>& model, int width, int height,
                      const Rigid3d& cam_from_ref);
// An equirectangular panorama of width x height, axes given by cam_from_ref.
GpuCamera pack_equirectangular(int width, int height, const Rigid3d& cam_from_ref);

// The model all of `cameras` share, or GpuModel::kAny when they differ (or there are none).
GpuModel common_model(std::span<const GpuCamera> cameras);
GpuModel common_model(const Rig& rig);

// The specialization constants of a camera kernel (shaders/include/camera.glsl): the model of
// its source cameras (the rig's) and of its targets. A fixed model compiles that model's code
// only; kAny keeps every model, chosen per camera at run time.
std::vector<gpu::SpecConstant> model_constants(GpuModel source, GpuModel target = GpuModel::kAny);

}  // namespace omnisweep::reproject
