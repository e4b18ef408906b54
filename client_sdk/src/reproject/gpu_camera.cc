#include "omnisweep/reproject/gpu_camera.h"

#include <cmath>
#include <stdexcept>

namespace omnisweep::reproject {
namespace {

GpuModel model_id(std::string_view name) {
  if (name == "ds") return GpuModel::kDoubleSphere;
  if (name == "kb4") return GpuModel::kKannalaBrandt;
  if (name == "eucm") return GpuModel::kExtendedUnified;
  if (name == "pinhole") return GpuModel::kPinhole;
  throw std::invalid_argument("camera model '" + std::string(name) + "' has no GPU implementation");
}

}  // namespace

namespace {

void set_pose(GpuCamera* g, const Rigid3d& cam_from_ref) {
  const Eigen::Matrix3d r = cam_from_ref.rotation.toRotationMatrix();
  for (int row = 0; row < 3; ++row) {
    for (int col = 0; col < 3; ++col) g->rows[row][col] = float(r(row, col));
    g->rows[row][3] = float(cam_from_ref.translation[row]);
  }
}

}  // namespace

void pack_rgba8(Rgb8View rgb, std::span<std::uint32_t> out) {
  const std::uint8_t* src = rgb.data();
  const std::size_t pixels = std::size_t(rgb.width()) * rgb.height();
  if (out.size() < pixels) throw std::invalid_argument("pack_rgba8: no room for every pixel");
  for (std::size_t p = 0; p < pixels; ++p) {
    out[p] = std::uint32_t(src[3 * p]) | (std::uint32_t(src[3 * p + 1]) << 8) |
             (std::uint32_t(src[3 * p + 2]) << 16) | 0xff000000u;
  }
}

GpuCamera pack_camera(const CameraModel<double>& model, int width, int height,
                      const Rigid3d& cam_from_ref) {
  GpuCamera g{};
  const auto params = model.params();
  for (int i = 0; i < 4; ++i) g.focal_center[i] = float(params[i]);
  for (std::size_t i = 4; i < params.size() && i < 8; ++i) g.extra[i - 4] = float(params[i]);
  set_pose(&g, cam_from_ref);
  g.model = std::uint32_t(model_id(model.name()));
  g.cos_max = float(std::cos(model.max_angle()));
  g.width = std::uint32_t(width);
  g.height = std::uint32_t(height);
  return g;
}

GpuCamera pack_equirectangular(int width, int height, const Rigid3d& cam_from_ref) {
  GpuCamera g{};
  set_pose(&g, cam_from_ref);
  g.model = std::uint32_t(GpuModel::kEquirectangular);
  g.cos_max = -2.0f;  // every direction is valid
  g.width = std::uint32_t(width);
  g.height = std::uint32_t(height);
  return g;
}

std::vector<GpuCamera> pack_cameras(const Rig& rig, int reference) {
  std::vector<GpuCamera> out;
  for (int c = 0; c < rig.num_cameras(); ++c) {
    const RigCamera& cam = rig.cameras[c];
    out.push_back(pack_camera(cam.model, cam.width, cam.height, rig.cam_from_cam(c, reference)));
  }
  return out;
}

void check_camera_records(std::size_t records) {
  if (records > kMaxCameraRecords) {
    throw std::invalid_argument(
        std::to_string(records) + " camera records for one kernel, at most " +
        std::to_string(kMaxCameraRecords) + " are supported (cameras x references)");
  }
}

GpuModel common_model(std::span<const GpuCamera> cameras) {
  if (cameras.empty()) return GpuModel::kAny;
  for (const GpuCamera& c : cameras) {
    if (c.model != cameras[0].model) return GpuModel::kAny;
  }
  return GpuModel(cameras[0].model);
}

GpuModel common_model(const Rig& rig) {
  if (rig.cameras.empty()) return GpuModel::kAny;
  const GpuModel first = model_id(rig.cameras[0].model.name());
  for (const RigCamera& cam : rig.cameras) {
    if (model_id(cam.model.name()) != first) return GpuModel::kAny;
  }
  return first;
}

std::vector<gpu::SpecConstant> model_constants(GpuModel source, GpuModel target) {
  return {gpu::SpecConstant::of(20, std::uint32_t(source)),
          gpu::SpecConstant::of(21, std::uint32_t(target))};
}

}  // namespace omnisweep::reproject
