#include "omnisweep/reproject/reprojector.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>

#include "omnisweep/gpu/buffer.h"
#include "omnisweep/gpu/sequence.h"
#include "omnisweep/reproject/forward_warp.h"

namespace omnisweep::reproject {

void ReprojectorOptions::check() const {
  if (!(min_distance > 0) || !(max_distance > min_distance))
    throw std::invalid_argument("reprojector: need 0 < min distance < max distance");
  if (!(max_splat >= 1.0) || !std::isfinite(max_splat)) {
    throw std::invalid_argument("reprojector: max splat " + std::to_string(max_splat) +
                                " must be at least 1 (pixels across)");
  }
  if (!(occlusion_tolerance >= 0 && occlusion_tolerance < 1))
    throw std::invalid_argument("reprojector: occlusion tolerance must lie in [0, 1)");
  if (max_inpaint_passes < 0 || max_inpaint_passes > 1024)
    throw std::invalid_argument("reprojector: max inpaint passes must lie in [0, 1024]");
  if (!(min_confidence >= 0 && min_confidence <= 1)) {
    throw std::invalid_argument("reprojector: min confidence " + std::to_string(min_confidence) +
                                " must lie in [0, 1]");
  }
}

Eigen::Quaterniond cube_face_rotation(CubeFace face) {
  // The face camera's z (forward) and y (down) axes in the view's frame; x = y cross z.
  const Eigen::Vector3d x = Eigen::Vector3d::UnitX(), y = Eigen::Vector3d::UnitY(),
                        z = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d forward = z, down = y;
  switch (face) {
    case CubeFace::kRight:
      forward = x;
      break;
    case CubeFace::kLeft:
      forward = -x;
      break;
    case CubeFace::kDown:
      forward = y, down = -z;
      break;
    case CubeFace::kUp:
      forward = -y, down = z;
      break;
    case CubeFace::kFront:
      break;
    case CubeFace::kBack:
      forward = -z;
      break;
  }
  Eigen::Matrix3d m;
  m.col(0) = down.cross(forward);
  m.col(1) = down;
  m.col(2) = forward;
  return Eigen::Quaterniond(m);
}

PinholeCamera<double> pinhole_for_fov(int width, int height, double horizontal_fov_deg) {
  if (width <= 0 || height <= 0 || width > 16384 || height > 16384)
    throw std::invalid_argument("pinhole view: size must be 1-16384 pixels per side");
  if (!(horizontal_fov_deg > 0 && horizontal_fov_deg < 179))
    throw std::invalid_argument("pinhole view: field of view must lie in (0, 179) degrees");
  const double f = 0.5 * width / std::tan(0.5 * horizontal_fov_deg * std::numbers::pi / 180);
  return PinholeCamera<double>({f, f, 0.5 * (width - 1), 0.5 * (height - 1)});
}

// A view to render: the target camera and its pixels per radian where it magnifies most (which
// bounds the widest hole a pose can open, in the target's pixels).
struct Target {
  GpuCamera camera;
  double pixels_per_radian = 0;
};

struct Reprojector::State {
  State(gpu::Context& c, const ReprojectorOptions& o) : context(&c), options(o) {}

  View render(const Target& target, int slot);
  // Warps, inpaints and samples colour for `target`; returns the warper holding the result and
  // the distance inpainting passes run.
  std::pair<ForwardWarper*, int> render_on_gpu(const Target& target, int slot);
  int copy_into(const std::pair<ForwardWarper*, int>& rendered, const ViewBuffers& out);

  gpu::Context* context;
  ReprojectorOptions options;
  std::optional<gpu::Buffer> distance;
  std::optional<gpu::Buffer> color;
  GpuCamera source{};
  Eigen::Vector3d viewpoint = Eigen::Vector3d::Zero();
  double nearest = 0;  // the panorama's nearest distance, at least min_distance
  // One warper per target model, size and slot (cube faces), reused as the pose changes.
  std::map<std::array<std::uint32_t, 4>, ForwardWarper> warpers;
  // One command buffer with its descriptor, command and query pools and fence, created with the
  // first render and re-recorded for every later one (nothing is allocated per render).
  std::optional<gpu::Sequence> sequence;
  double last_gpu_ms = 0;
};

Reprojector::Reprojector(gpu::Context& context, const ReprojectorOptions& options) {
  options.check();
  state_ = std::make_unique<State>(context, options);
}

Reprojector::~Reprojector() = default;
Reprojector::Reprojector(Reprojector&&) noexcept = default;
Reprojector& Reprojector::operator=(Reprojector&&) noexcept = default;

double Reprojector::last_gpu_ms() const { return state_->last_gpu_ms; }

void Reprojector::set_panorama(Rgb8View color, FloatView distance, const Eigen::Vector3d& viewpoint,
                               FloatView confidence) {
  if (confidence.empty() || state_->options.min_confidence <= 0) {
    set_panorama(color, distance, viewpoint);
    return;
  }
  if (confidence.width() != distance.width() || confidence.height() != distance.height()) {
    throw std::invalid_argument("reprojector: the confidence is " +
                                std::to_string(confidence.width()) + "x" +
                                std::to_string(confidence.height()) + ", not the distance's size");
  }
  // Low-confidence distances become holes, which the warp's inpainting fills from around them.
  FloatImage trusted = FloatImage::copy_of(distance);
  for (std::size_t i = 0; i < trusted.size(); ++i) {
    if (!(confidence.data()[i] >= state_->options.min_confidence)) trusted.data()[i] = 0.0f;
  }
  set_panorama(color, trusted, viewpoint);
}

void Reprojector::set_panorama(Rgb8View color, FloatView distance,
                               const Eigen::Vector3d& viewpoint) {
  if (color.width() != distance.width() || color.height() != distance.height() ||
      color.width() != 2 * color.height() || color.height() <= 0) {
    throw std::invalid_argument(
        "reprojector: the panorama needs colour and distance of the same 2:1 size, "
        "got " +
        std::to_string(color.width()) + "x" + std::to_string(color.height()) + " and " +
        std::to_string(distance.width()) + "x" + std::to_string(distance.height()));
  }
  State& st = *state_;
  const GpuCamera source = pack_equirectangular(color.width(), color.height(), Rigid3d());
  const std::size_t pixels = std::size_t(color.width()) * color.height();
  if (source.width != st.source.width || source.height != st.source.height) {
    st.warpers.clear();
    st.distance.emplace(*st.context, pixels * 4);
    st.color.emplace(*st.context, pixels * 4);
  }
  st.source = source;
  std::vector<std::uint32_t> packed(pixels);
  pack_rgba8(color, packed);
  st.color->upload(std::span<const std::uint32_t>(packed));
  st.distance->upload(distance.data(), distance.size() * sizeof(float));
  st.viewpoint = viewpoint;
  st.nearest = st.options.max_distance;
  for (std::size_t i = 0; i < distance.size(); ++i) {
    const float d = distance.data()[i];
    if (d > 0 && d < st.nearest) st.nearest = d;
  }
  st.nearest = std::max(st.nearest, st.options.min_distance);
}

View Reprojector::State::render(const Target& target, int slot) {
  const auto [warper, passes] = render_on_gpu(target, slot);
  return View{warper->download_color(), warper->download(), passes};
}

int Reprojector::State::copy_into(const std::pair<ForwardWarper*, int>& rendered,
                                  const ViewBuffers& out) {
  const ForwardWarper& warper = *rendered.first;
  const vk::DeviceSize bytes = vk::DeviceSize(warper.target().width) * warper.target().height * 4;
  context->run_commands([&](const vk::raii::CommandBuffer& cmd) {
    // The kernels' writes (earlier submissions on this queue) before the copies read them.
    const vk::MemoryBarrier written(vk::AccessFlagBits::eShaderWrite,
                                    vk::AccessFlagBits::eTransferRead);
    cmd.pipelineBarrier(vk::PipelineStageFlagBits::eComputeShader,
                        vk::PipelineStageFlagBits::eTransfer, {}, written, {}, {});
    if (out.color)
      cmd.copyBuffer(warper.color_result().handle(), out.color,
                     vk::BufferCopy(0, out.color_offset, bytes));
    if (out.distance)
      cmd.copyBuffer(warper.result().handle(), out.distance,
                     vk::BufferCopy(0, out.distance_offset, bytes));
  });
  return rendered.second;
}

std::pair<ForwardWarper*, int> Reprojector::State::render_on_gpu(const Target& view, int slot) {
  if (!distance) throw std::logic_error("reprojector: set_panorama before rendering");
  const GpuCamera& target = view.camera;
  // Widest disocclusion this pose can open: the parallax between the panorama's nearest
  // surface and d_max.
  const Eigen::Vector3d t(target.rows[0][3], target.rows[1][3], target.rows[2][3]);
  const double hole = t.norm() * (1 / nearest - 1 / options.max_distance) * view.pixels_per_radian;
  const int max_passes = int(std::min<double>(options.max_inpaint_passes, std::ceil(hole) + 4));

  const std::array<std::uint32_t, 4> key = {target.model, target.width, target.height,
                                            std::uint32_t(slot)};
  auto it = warpers.find(key);
  if (it == warpers.end()) {
    const WarpOptions warp{.min_distance = options.min_distance,
                           .max_distance = options.max_distance,
                           .inpaint_passes = max_passes,
                           .max_splat = options.max_splat,
                           .color = true,
                           .occlusion_tolerance = options.occlusion_tolerance};
    it = warpers.try_emplace(key, *context, source, target, warp).first;
  } else {
    it->second.set_target(target);
  }
  ForwardWarper& warper = it->second;
  // Passes in batches until one fills nothing: holes are usually far narrower than the bound.
  constexpr int kBatch = 8;
  if (!sequence) sequence.emplace(*context, kBatch + 8, 2);
  gpu::Sequence& seq = *sequence;
  double gpu_ms = 0;
  seq.begin();
  seq.begin_stage("warp");
  warper.record_warp(seq, *distance);
  const int passes = warper.inpaint_until_filled(seq, max_passes, kBatch, &gpu_ms);
  seq.begin();
  seq.begin_stage("colour");
  warper.record_color_sample(seq, *distance, *color);
  warper.inpaint_color_until_filled(seq, max_passes, kBatch, &gpu_ms);
  last_gpu_ms = gpu_ms;
  return {&warper, passes};
}

namespace {

// view_from_pano for a view at rig_from_view when the panorama sits at `viewpoint`.
Rigid3d view_from_panorama(const Rigid3d& rig_from_view, const Eigen::Vector3d& viewpoint) {
  return rig_from_view.inverse() * Rigid3d(Eigen::Quaterniond::Identity(), viewpoint);
}

void check_size(int width, int height, const char* what) {
  if (width <= 0 || height <= 0 || width > 16384 || height > 16384)
    throw std::invalid_argument(std::string("reprojector: ") + what +
                                " size must be 1-16384 pixels per side");
}

Target panorama_target(const Rigid3d& rig_from_view, const Eigen::Vector3d& viewpoint, int width,
                       int height) {
  check_size(width, height, "panorama");
  return {pack_equirectangular(width, height, view_from_panorama(rig_from_view, viewpoint)),
          width / (2 * std::numbers::pi)};
}

// Pixels per radian at a pinhole image's widest point, where it magnifies most.
double pinhole_pixels_per_radian(const PinholeCamera<double>& camera, int width, int height) {
  const auto p = camera.params();
  const double edge = std::max({p[2], width - 1 - p[2], p[3], height - 1 - p[3]});
  const double f = std::max(p[0], p[1]);
  return f * (1 + (edge / f) * (edge / f));
}

Target pinhole_target(const Rigid3d& rig_from_view, const Eigen::Vector3d& viewpoint,
                      const PinholeCamera<double>& camera, int width, int height,
                      const char* what = "pinhole view") {
  check_size(width, height, what);
  return {pack_camera(CameraModel<double>(camera), width, height,
                      view_from_panorama(rig_from_view, viewpoint)),
          pinhole_pixels_per_radian(camera, width, height)};
}

}  // namespace

View Reprojector::render_panorama(const Rigid3d& rig_from_view, int width, int height) {
  return state_->render(panorama_target(rig_from_view, state_->viewpoint, width, height), 0);
}

View Reprojector::render_pinhole(const Rigid3d& rig_from_view, const PinholeCamera<double>& camera,
                                 int width, int height) {
  return state_->render(pinhole_target(rig_from_view, state_->viewpoint, camera, width, height), 0);
}

int Reprojector::render_panorama_into(const Rigid3d& rig_from_view, int width, int height,
                                      const ViewBuffers& out) {
  return state_->copy_into(
      state_->render_on_gpu(panorama_target(rig_from_view, state_->viewpoint, width, height), 0),
      out);
}

int Reprojector::render_pinhole_into(const Rigid3d& rig_from_view,
                                     const PinholeCamera<double>& camera, int width, int height,
                                     const ViewBuffers& out) {
  return state_->copy_into(
      state_->render_on_gpu(pinhole_target(rig_from_view, state_->viewpoint, camera, width, height),
                            0),
      out);
}

std::array<View, 6> Reprojector::render_cube_map(const Rigid3d& rig_from_view, int face_size) {
  check_size(face_size, face_size, "cube face");
  const PinholeCamera<double> camera = pinhole_for_fov(face_size, face_size, 90);
  std::array<View, 6> faces;
  for (int f = 0; f < 6; ++f) {
    const Rigid3d view_from_face(cube_face_rotation(CubeFace(f)), Eigen::Vector3d::Zero());
    faces[f] = state_->render(pinhole_target(rig_from_view * view_from_face, state_->viewpoint,
                                             camera, face_size, face_size, "cube face"),
                              1 + f);
  }
  return faces;
}

}  // namespace omnisweep::reproject
