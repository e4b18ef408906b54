#include "server/depth/gpu_photometric_correction.h"

#include <Eigen/Core>
#include <array>
#include <numeric>
#include <stdexcept>
#include <string>

namespace omnisweep::depth {

namespace {

struct CorrectionPush {
  std::uint32_t width, height, images;
};

std::vector<int> all_or(std::vector<int> cameras, const Rig& rig) {
  if (!cameras.empty()) return cameras;
  std::vector<int> all(std::size_t(rig.num_cameras()));
  std::iota(all.begin(), all.end(), 0);
  return all;
}

// The cameras' common size; throws where they have none.
const RigCamera& first_camera(const Rig& rig, const std::vector<int>& cameras) {
  if (cameras.empty()) throw std::invalid_argument("photometric correction: no cameras");
  for (const int c : cameras) {
    if (c < 0 || c >= rig.num_cameras())
      throw std::invalid_argument("photometric correction: no camera " + std::to_string(c));
    if (rig.cameras[c].width != rig.cameras[cameras[0]].width ||
        rig.cameras[c].height != rig.cameras[cameras[0]].height)
      throw std::invalid_argument("photometric correction: the cameras must share one size");
  }
  return rig.cameras[std::size_t(cameras[0])];
}

}  // namespace

GpuPhotometricCorrection::GpuPhotometricCorrection(gpu::Context& context, const Rig& rig,
                                                   std::vector<int> cameras)
    : cameras_(all_or(std::move(cameras), rig)),
      width_(first_camera(rig, cameras_).width),
      height_(rig.cameras[std::size_t(cameras_[0])].height),
      kernel_(context, gpu::Shader::kPhotometricCorrection,
              {.bindings = {1, 1, 1},
               .push_constant_bytes = sizeof(CorrectionPush),
               .local_size = {8, 8, 1},
               .constants = {}}),
      angles_(context, (std::uint64_t(width_) * height_ * cameras_.size() + 1) / 2 * 4),
      responses_(context, sizeof(float) * 8 * cameras_.size()) {
  // Only these cameras' tables: a colour rig's other cameras are not corrected here. Stored as
  // 16-bit floats, two to a uint (vignetting_angles has rounded them so already).
  std::vector<Eigen::half> halves;
  halves.reserve(std::size_t(angles_.size() / 2));
  for (const int c : cameras_)
    for (const float t2 : vignetting_angles(rig.cameras[std::size_t(c)])) halves.emplace_back(t2);
  if (halves.size() % 2 != 0) halves.emplace_back(-1.0f);
  angles_.upload(halves.data(), halves.size() * sizeof(Eigen::half));
}

void GpuPhotometricCorrection::record(gpu::Sequence& seq, gpu::Buffer& images,
                                      const PhotometryFit& fit) {
  std::vector<std::array<float, 8>> responses;
  for (const int c : cameras_) {
    if (c >= int(fit.cameras.size()))
      throw std::invalid_argument("photometric correction: the fit has no camera " +
                                  std::to_string(c));
    const CameraPhotometry& r = fit.cameras[std::size_t(c)];
    responses.push_back({float(1.0 / r.gain[0]), float(1.0 / r.gain[1]), float(1.0 / r.gain[2]),
                         float(r.b1), float(r.b2), 0.f, 0.f, 0.f});
  }
  responses_.upload(responses.data(), responses.size() * sizeof(responses[0]));
  const CorrectionPush push{std::uint32_t(width_), std::uint32_t(height_),
                            std::uint32_t(cameras_.size())};
  seq.dispatch(kernel_, {images, angles_, responses_}, push,
               kernel_.groups_for(width_, height_, int(cameras_.size())));
  seq.barrier();
}

}  // namespace omnisweep::depth
