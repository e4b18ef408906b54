#include "server/stitch/stitcher.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace omnisweep::stitch {
namespace {

Eigen::Vector3d mean_position(const Rig& rig, const std::vector<int>& references) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (int r : references) sum += rig.cameras.at(r).center_in_rig();
  return sum / double(references.size());
}

std::uint64_t area(const RigCamera& c) { return std::uint64_t(c.width) * c.height; }

// The model of the merge's cameras (both rigs'), where they share one.
reproject::GpuModel merge_model(const Rig& matching, const Rig& color) {
  const reproject::GpuModel m = reproject::common_model(matching);
  return m == reproject::common_model(color) ? m : reproject::GpuModel::kAny;
}

struct MergePush {
  std::uint32_t width, height, references;
};

struct MergeConfidencePush {
  std::uint32_t width, height, references, has_confidence;
  float tolerance;
};

struct BoxPush {
  std::uint32_t width, height, layers;
  std::int32_t radius;
  std::uint32_t axis, wrap;
  float border;
};

struct WeightsPush {
  std::uint32_t width, height, references;
  float d_min, d_max;
};

}  // namespace

void StitchOptions::check() const {
  if (panorama_width != 2 * panorama_height || panorama_height < 4 || panorama_height > 8192) {
    throw std::invalid_argument(
        "StitchOptions.panorama_width x panorama_height = " + std::to_string(panorama_width) + "x" +
        std::to_string(panorama_height) +
        " (panorama-resolution): width must be twice the height, height within [4, 8192]");
  }
  reproject::check_warp_range("StitchOptions", min_distance, max_distance, inpaint_passes);
  if (viewpoint && !viewpoint->allFinite())
    throw std::invalid_argument("StitchOptions.viewpoint: must be finite");
  if (temporal) temporal->check();
  if (!(confidence_tolerance > 0) || !std::isfinite(confidence_tolerance)) {
    throw reproject::option_error("StitchOptions", "confidence_tolerance", confidence_tolerance,
                                  "a positive number (1/m)");
  }
  if (!(plane_fill >= 0 && plane_fill < 1))
    throw reproject::option_error("StitchOptions", "plane_fill", plane_fill,
                                  "a confidence in [0, 1) (0: off)");
  const int cell = MembraneFillParams::for_width(panorama_width).cell;
  if (membrane_fill && (panorama_width % cell != 0 || panorama_height % cell != 0)) {
    throw std::invalid_argument("StitchOptions.membrane_fill: the panorama " +
                                std::to_string(panorama_width) + "x" +
                                std::to_string(panorama_height) + " is not a whole number of " +
                                std::to_string(cell) + "-pixel cells of the membrane fill");
  }
}

Stitcher::Stitcher(gpu::Context& context, const Rig& matching_rig, const Rig& color_rig,
                   const std::vector<int>& references,
                   const std::vector<std::optional<Gray8Image>>& usable,
                   const StitchOptions& options)
    : context_(&context),
      options_(options),
      references_(references),
      matching_rig_(matching_rig),
      color_rig_(color_rig),
      viewpoint_(options.viewpoint ? *options.viewpoint : mean_position(matching_rig, references)),
      allocated_before_(context.allocated_bytes()),
      distances_(context, references.size() * area(matching_rig.cameras.at(references.at(0))) * 4),
      confidences_(context, distances_.size()),
      cameras_(context, 2 * references.size() * sizeof(reproject::GpuCamera)),
      weights_(context, references.size() * std::uint64_t(options.panorama_width) *
                            options.panorama_height * 4),
      color_(context, references.size() * area(color_rig.cameras.at(references.at(0))) * 4),
      out_color_(context, std::uint64_t(options.panorama_width) * options.panorama_height * 4),
      out_distance_(context, std::uint64_t(options.panorama_width) * options.panorama_height * 4),
      out_confidence_(context, out_distance_.size()),
      merge_(context, gpu::Shader::kStitchMerge,
             {.bindings = {reproject::camera_binding(), gpu::BindingSlot::texels(),
                           gpu::BindingSlot::texels(), gpu::BindingSlot::texels(),
                           gpu::BindingSlot::texels(), 1, 1, gpu::BindingSlot::texels(), 1},
              .push_constant_bytes = sizeof(MergeConfidencePush),
              .constants = reproject::model_constants(merge_model(matching_rig, color_rig))}),
      sequence_(context) {
  options.check();
  const RigCamera& first = matching_rig.cameras[references[0]];
  const RigCamera& first_color = color_rig.cameras[references[0]];
  std::vector<reproject::GpuCamera> cameras;
  std::vector<reproject::WarpLayer> layers;
  for (int ref : references) {
    const RigCamera& cam = matching_rig.cameras.at(ref);
    const RigCamera& color_cam = color_rig.cameras.at(ref);
    if (cam.width != first.width || cam.height != first.height ||
        color_cam.width != first_color.width || color_cam.height != first_color.height) {
      throw std::invalid_argument(
          "reference cameras must share one matching and one colour resolution");
    }
    const Rigid3d cam_from_rig = cam.rig_from_cam.inverse();
    const Eigen::Vector3d t_c = cam_from_rig * viewpoint_;  // the viewpoint in c's frame
    // Warp target: c's own intrinsics and axes, centred on the viewpoint (P = D ray - t_c).
    layers.push_back({reproject::pack_camera(cam.model, cam.width, cam.height, Rigid3d()),
                      reproject::pack_camera(cam.model, cam.width, cam.height,
                                             Rigid3d(Eigen::Quaterniond::Identity(), -t_c))});
    cameras.push_back(reproject::pack_camera(cam.model, cam.width, cam.height,
                                             Rigid3d(cam_from_rig.rotation, t_c)));
    cameras.push_back(
        reproject::pack_camera(color_cam.model, color_cam.width, color_cam.height, Rigid3d()));
  }
  cameras_.upload(cameras.data(), cameras.size() * sizeof(reproject::GpuCamera));
  warper_.emplace(
      context, std::move(layers),
      reproject::WarpOptions{options.min_distance, options.max_distance, options.inpaint_passes});

  compute_weights(usable);
  if (options.plane_fill > 0) {
    plane_fill_.emplace(context, options.panorama_width, options.panorama_height,
                        options.plane_fill, options.min_distance, options.max_distance);
    merged_distance_.emplace(context, out_distance_.size());
  }
  if (options.region_planes)
    region_planes_.emplace(context, options.panorama_width, options.panorama_height,
                           RegionPlaneParams::for_width(options.panorama_width),
                           options.min_distance, options.max_distance);
  if (options.edge_check)
    edge_check_.emplace(context, options.panorama_width, options.panorama_height,
                        EdgeCheckParams::for_width(options.panorama_width));
  if (options.membrane_fill)
    membrane_fill_.emplace(context, options.panorama_width, options.panorama_height,
                           MembraneFillParams::for_width(options.panorama_width),
                           options.min_distance, options.max_distance);
  if (options.temporal)
    temporal_.emplace(context, options.panorama_width, options.panorama_height, *options.temporal);
  gpu_bytes_ = context.allocated_bytes() - allocated_before_;
}

void Stitcher::compute_weights(const std::vector<std::optional<Gray8Image>>& usable) {
  gpu::Context& context = *context_;
  const RigCamera& first = matching_rig_.cameras[references_[0]];
  const auto w = std::uint32_t(first.width), h = std::uint32_t(first.height);
  const auto pw = std::uint32_t(options_.panorama_width),
             ph = std::uint32_t(options_.panorama_height);
  const auto layers = std::uint32_t(references_.size());
  // Usable masks as 0/1 floats, one per reference.
  std::vector<float> masks(std::size_t(w) * h * layers, 1.0f);
  for (std::size_t k = 0; k < references_.size(); ++k) {
    const int ref = references_[k];
    if (usable.empty() || !usable[ref]) continue;
    for (std::size_t i = 0; i < std::size_t(w) * h; ++i)
      masks[k * w * h + i] = usable[ref]->data()[i] ? 1.0f : 0.0f;
  }
  gpu::Buffer mask_buffer(context, masks.size() * 4), mask_tmp(context, masks.size() * 4),
      weight_tmp(context, weights_.size());
  mask_buffer.upload(std::span<const float>(masks));
  const gpu::Kernel box(context, gpu::Shader::kBoxFilter,
                        {.bindings = {1, 1}, .push_constant_bytes = sizeof(BoxPush)});
  const gpu::Kernel raw(
      context, gpu::Shader::kBlendWeights,
      {.bindings = {reproject::camera_binding(), 1, 1},
       .push_constant_bytes = sizeof(WeightsPush),
       .constants = reproject::model_constants(reproject::common_model(matching_rig_))});
  const gpu::Kernel normalise(context, gpu::Shader::kNormalizeWeights,
                              {.bindings = {1}, .push_constant_bytes = sizeof(MergePush)});
  gpu::Sequence seq(context, 16, 1);
  seq.begin();
  // A 31x31 box in two passes over `layers` images, through `scratch`.
  auto box_31 = [&](gpu::Buffer& image, gpu::Buffer& scratch, std::uint32_t width,
                    std::uint32_t height, std::uint32_t wrap_x, float border) {
    seq.dispatch(box, {image, scratch}, BoxPush{width, height, layers, 15, 0, wrap_x, border},
                 box.groups_for(width, height, layers));
    seq.barrier();
    seq.dispatch(box, {scratch, image}, BoxPush{width, height, layers, 15, 1, 0, border},
                 box.groups_for(width, height, layers));
    seq.barrier();
  };
  box_31(mask_buffer, mask_tmp, w, h, 0, 1.0f);  // masks: the border padded with 1
  seq.dispatch(
      raw, {cameras_, mask_buffer, weights_},
      WeightsPush{pw, ph, layers, float(options_.min_distance), float(options_.max_distance)},
      raw.groups_for(pw, ph));
  seq.barrier();
  const MergePush planes{pw, ph, layers};
  seq.dispatch(normalise, {weights_}, planes, normalise.groups_for(pw, ph));
  seq.barrier();
  // Smoothed with a 31x31 box that wraps around horizontally, then normalised again.
  box_31(weights_, weight_tmp, pw, ph, 1, 0.0f);
  seq.dispatch(normalise, {weights_}, planes, normalise.groups_for(pw, ph));
  seq.submit_and_wait();
}

std::vector<FloatImage> Stitcher::weights() const {
  std::vector<FloatImage> out;
  const std::size_t plane = std::size_t(options_.panorama_width) * options_.panorama_height;
  for (std::size_t k = 0; k < references_.size(); ++k) {
    out.emplace_back(options_.panorama_width, options_.panorama_height);
    weights_.download(out.back().data(), plane * 4, k * plane * 4);
  }
  return out;
}

void Stitcher::check_color(std::span<const Rgb8View> color) const {
  if (color.size() != references_.size())
    throw std::invalid_argument("stitch: expected one colour image per reference");
  const RigCamera& first_color = color_rig_.cameras[references_[0]];
  for (std::size_t k = 0; k < references_.size(); ++k) {
    if (color[k].width() != first_color.width || color[k].height() != first_color.height) {
      throw std::invalid_argument("stitch: colour image of reference " +
                                  std::to_string(references_[k]) +
                                  " is not at the colour resolution");
    }
  }
}

void Stitcher::upload_color(std::span<const Rgb8View> color) {
  check_color(color);
  const std::uint64_t color_area = area(color_rig_.cameras[references_[0]]);
  std::vector<std::uint32_t> packed(color_area);
  for (std::size_t k = 0; k < references_.size(); ++k) {
    reproject::pack_rgba8(color[k], packed);
    color_.upload(packed.data(), color_area * 4, k * color_area * 4);
  }
}

void Stitcher::record(gpu::Sequence& seq, const gpu::Buffer& distance,
                      const gpu::Buffer* confidence) {
  const std::uint64_t matching = area(matching_rig_.cameras[references_[0]]);
  if (distance.size() < references_.size() * matching * 4)
    throw std::invalid_argument(
        "stitch: the distance buffer holds fewer than the references' maps");
  if (confidence && confidence->size() < references_.size() * matching * 4)
    throw std::invalid_argument(
        "stitch: the confidence buffer holds fewer than the references' maps");
  seq.begin_stage("warp");
  warper_->record(seq, distance);  // ends in a barrier
  seq.begin_stage("merge");
  const bool fill = plane_fill_ && confidence;
  gpu::Buffer& merged = fill ? *merged_distance_ : out_distance_;
  seq.dispatch(merge_,
               {cameras_, gpu::Texels(weights_, gpu::TexelFormat::kR32Float),
                gpu::Texels(warper_->result(), gpu::TexelFormat::kR32Uint),
                gpu::Texels(distance, gpu::TexelFormat::kR32Float),
                gpu::Texels(color_, gpu::TexelFormat::kR32Uint), out_color_, merged,
                gpu::Texels(confidence ? *confidence : distance, gpu::TexelFormat::kR32Float),
                out_confidence_},
               MergeConfidencePush{std::uint32_t(options_.panorama_width),
                                   std::uint32_t(options_.panorama_height),
                                   std::uint32_t(references_.size()), confidence ? 1u : 0u,
                                   float(options_.confidence_tolerance)},
               merge_.groups_for(options_.panorama_width, options_.panorama_height));
  if (fill) {
    seq.barrier();
    seq.begin_stage("plane fill");
    plane_fill_->record(seq, out_color_, merged, out_confidence_, out_distance_);
  }
  if (region_planes_ && confidence) {
    seq.barrier();
    seq.begin_stage("region planes");
    region_planes_->record(seq, out_distance_, out_confidence_);
  }
  if (edge_check_ && confidence) {
    seq.barrier();
    seq.begin_stage("edge check");
    edge_check_->record(seq, out_color_, out_distance_, out_confidence_);
  }
  if (membrane_fill_ && confidence) {
    seq.barrier();
    seq.begin_stage("membrane fill");
    membrane_fill_->record(seq, out_distance_, out_confidence_);
  }
  if (temporal_) {
    seq.barrier();
    temporal_->record(seq, out_distance_, out_color_, out_confidence_);
  }
  seq.end_stage();
}

Panorama Stitcher::download() const {
  Panorama out{Rgb8Image(options_.panorama_width, options_.panorama_height),
               FloatImage(options_.panorama_width, options_.panorama_height),
               FloatImage(options_.panorama_width, options_.panorama_height),
               {}};
  out_distance_.download(out.distance.data(), out.distance.size() * 4);
  out_confidence_.download(out.confidence.data(), out.confidence.size() * 4);
  std::vector<std::uint32_t> rgba(out.distance.size());
  out_color_.download(rgba.data(), rgba.size() * 4);
  for (std::size_t p = 0; p < rgba.size(); ++p) {
    for (int c = 0; c < 3; ++c)
      out.rgb.data()[3 * p + c] = std::uint8_t((rgba[p] >> (8 * c)) & 255);
  }
  return out;
}

Panorama Stitcher::stitch(std::span<const FloatView> distance, std::span<const Rgb8View> color,
                          std::span<const FloatView> confidence) {
  if (distance.size() != references_.size() || color.size() != references_.size()) {
    throw std::invalid_argument(
        "stitch: expected one distance map and one colour image per reference");
  }
  if (!confidence.empty() && confidence.size() != references_.size())
    throw std::invalid_argument("stitch: expected one confidence map per reference, or none");
  const RigCamera& first = matching_rig_.cameras[references_[0]];
  for (std::size_t k = 0; k < references_.size(); ++k) {
    if (distance[k].width() != first.width || distance[k].height() != first.height) {
      throw std::invalid_argument("stitch: distance map of reference " +
                                  std::to_string(references_[k]) +
                                  " is not at the matching resolution");
    }
  }
  upload_color(color);
  for (std::size_t k = 0; k < references_.size(); ++k)
    distances_.upload(distance[k].data(), area(first) * 4, k * area(first) * 4);
  for (std::size_t k = 0; k < confidence.size(); ++k) {
    if (confidence[k].width() != first.width || confidence[k].height() != first.height)
      throw std::invalid_argument("stitch: confidence map of reference " +
                                  std::to_string(references_[k]) +
                                  " is not at the matching resolution");
    confidences_.upload(confidence[k].data(), area(first) * 4, k * area(first) * 4);
  }
  sequence_.begin();
  record(sequence_, distances_, confidence.empty() ? nullptr : &confidences_);
  sequence_.submit_and_wait();
  Panorama out = download();
  out.stage_ms = sequence_.stage_ms();
  return out;
}

}  // namespace omnisweep::stitch
