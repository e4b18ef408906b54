#include "server/depth/depth_estimator.h"

#include <stdexcept>

#include "omnisweep/reproject/gpu_camera.h"

namespace omnisweep::depth {
namespace {

struct SelectionPush {
  std::uint32_t width, height, num_cameras, reference;
  float d_min, d_max;
};
struct GuidePush {
  std::uint32_t width, height, camera;
};
struct SweepPush {
  std::uint32_t width, height, reference, num_candidates;
  float inv_d_min, inv_d_max;
};
struct WtaPush {
  std::uint32_t width, height, num_candidates;
  float inv_d_min, inv_d_max, d_max;
};

// `layout` with the camera kernels' model constants for `rig`'s cameras.
gpu::KernelLayout with_rig_model(gpu::KernelLayout layout, const Rig& rig) {
  const auto models = reproject::model_constants(reproject::common_model(rig));
  layout.constants.insert(layout.constants.end(), models.begin(), models.end());
  return layout;
}

const Rig& checked(const Rig& rig, const DepthOptions& options) {
  options.check(rig.num_cameras());
  rig.check();
  for (int c = 0; c < rig.num_cameras(); ++c) {
    if (rig.cameras[c].width != options.matching_width ||
        rig.cameras[c].height != options.matching_height) {
      throw std::invalid_argument(
          "camera " + std::to_string(c) + " is calibrated at " +
          std::to_string(rig.cameras[c].width) + "x" + std::to_string(rig.cameras[c].height) +
          "; resize the rig to the matching resolution " + std::to_string(options.matching_width) +
          "x" + std::to_string(options.matching_height));
    }
  }
  return rig;
}

}  // namespace

DepthEstimator::DepthEstimator(gpu::Context& context, const Rig& rig,
                               const std::vector<std::optional<Gray8Image>>& usable,
                               const DepthOptions& options)
    : context_(&context),
      allocated_before_(context.allocated_bytes()),
      options_(options),
      rig_(checked(rig, options)),
      width_(options.matching_width),
      height_(options.matching_height),
      layout_(plan_volume(context, width_, height_, options.num_candidates, options.half_costs)),
      selection_kernel_(context, "camera_selection",
                        {.bindings = {1, 1, 1},
                         .push_constant_bytes = sizeof(SelectionPush),
                         .constants = reproject::model_constants(reproject::common_model(rig))}),
      guide_kernel_(context, "ycbcr_guide",
                    {.bindings = {1, 1}, .push_constant_bytes = sizeof(GuidePush)}),
      sweep_kernel_(context, volume_shader("sphere_sweep_cost", layout_),
                    with_rig_model(
                        volume_kernel_layout({1, 1, 1, kMaxChunks}, sizeof(SweepPush), layout_),
                        rig)),
      wta_kernel_(context, volume_shader("winner_take_all", layout_),
                  volume_kernel_layout({kMaxChunks, 1}, sizeof(WtaPush), layout_)),
      volume_(context, width_, height_, layout_),
      filter_(context, width_, height_, layout_),
      post_filter_(context, width_, height_, VolumeLayout{1, 1}),
      images_(context, std::uint64_t(width_) * height_ * 4 * rig.num_cameras()),
      guide_(context, std::uint64_t(width_) * height_ * 4),
      dummy_(context, 16),
      sequence_(context) {
  if (usable.size() != std::size_t(rig.num_cameras()) && !usable.empty()) {
    throw std::invalid_argument("expected one mask (or none) per camera, got " +
                                std::to_string(usable.size()));
  }
  // Usable masks, one byte per pixel, camera after camera.
  const std::size_t pixels = std::size_t(width_) * height_;
  std::vector<std::uint8_t> mask_bytes(pixels * rig.num_cameras(), 255);
  for (std::size_t c = 0; c < usable.size(); ++c) {
    if (!usable[c]) continue;
    if (usable[c]->width() != width_ || usable[c]->height() != height_) {
      throw std::invalid_argument(
          "mask of camera " + std::to_string(c) + " is " + std::to_string(usable[c]->width()) +
          "x" + std::to_string(usable[c]->height()) + ", expected the matching resolution");
    }
    for (std::size_t p = 0; p < pixels; ++p)
      mask_bytes[c * pixels + p] = usable[c]->data()[p] ? 255 : 0;
  }
  mask_bytes.resize((mask_bytes.size() + 3) / 4 * 4, 0);
  gpu::Buffer masks(context, mask_bytes.size());
  masks.upload(mask_bytes.data(), mask_bytes.size());

  // Camera selection, once per calibration (ALGORITHM.md §3 step 2).
  sequence_.begin();
  for (std::size_t slot = 0; slot < options.references.size(); ++slot) {
    const int reference = options.references[slot];
    const std::vector<reproject::GpuCamera> packed = reproject::pack_cameras(rig_, reference);
    cameras_.emplace_back(context, packed.size() * sizeof(reproject::GpuCamera));
    cameras_.back().upload(packed.data(), packed.size() * sizeof(reproject::GpuCamera));
    selections_.emplace_back(context, pixels * sizeof(std::int32_t));
    distances_.emplace_back(context, width_, height_, VolumeLayout{1, 1});
    sequence_.dispatch(selection_kernel_, {cameras_.back(), masks, selections_.back()},
                       SelectionPush{std::uint32_t(width_), std::uint32_t(height_),
                                     std::uint32_t(rig.num_cameras()), std::uint32_t(reference),
                                     float(options.min_distance), float(options.max_distance)},
                       selection_kernel_.groups_for(width_, height_));
  }
  sequence_.submit_and_wait();
  gpu_bytes_ = context.allocated_bytes() - masks.size() - allocated_before_;
}

std::uint64_t DepthEstimator::gpu_bytes() const { return gpu_bytes_; }

void DepthEstimator::upload_images(const std::vector<const Rgb8Image*>& images) {
  if (images.size() != std::size_t(rig_.num_cameras())) {
    throw std::invalid_argument("expected " + std::to_string(rig_.num_cameras()) + " images, got " +
                                std::to_string(images.size()));
  }
  const std::size_t pixels = std::size_t(width_) * height_;
  std::vector<std::uint32_t> packed(pixels * images.size());
  for (std::size_t c = 0; c < images.size(); ++c) {
    const Rgb8Image& im = *images[c];
    if (im.width() != width_ || im.height() != height_ || im.channels() != 3) {
      throw std::invalid_argument("image of camera " + std::to_string(c) + " is " +
                                  std::to_string(im.width()) + "x" + std::to_string(im.height()) +
                                  "x" + std::to_string(im.channels()) +
                                  ", expected RGB at the matching resolution " +
                                  std::to_string(width_) + "x" + std::to_string(height_));
    }
    reproject::pack_rgba8(im, std::span(packed).subspan(c * pixels, pixels));
  }
  images_.upload(std::span<const std::uint32_t>(packed));
}

void DepthEstimator::record_reference(gpu::Sequence& seq, int slot, bool filter, bool finish) {
  const int reference = options_.references[slot];
  const auto groups = sweep_kernel_.groups_for(width_, height_);
  const float inv_d_min = float(1.0 / options_.min_distance),
              inv_d_max = float(1.0 / options_.max_distance);
  const GuidePush guide_push{std::uint32_t(width_), std::uint32_t(height_),
                             std::uint32_t(reference)};

  // Winner takes all in the filter's last pass (the volume is not written back) wherever there
  // is a filter with a last upsample; otherwise its own kernel reads the volume.
  const bool fused_winner = filter && finish && filter_.levels() >= 2;

  seq.begin_stage("sweep_cost");
  seq.dispatch(sweep_kernel_, {cameras_[slot], images_, selections_[slot], volume_.binding(dummy_)},
               SweepPush{std::uint32_t(width_), std::uint32_t(height_), std::uint32_t(reference),
                         std::uint32_t(options_.num_candidates), inv_d_min, inv_d_max},
               groups);
  seq.barrier();
  if (filter) {
    seq.begin_stage("filter");
    seq.dispatch(guide_kernel_, {images_, guide_}, guide_push, groups);
    seq.barrier();
    const IsbParams params{options_.sigma_i, options_.scaled_sigma_s()};
    if (fused_winner) {
      filter_.record_winner_take_all(
          seq, guide_, volume_, params, distances_[slot].chunks()[0],
          {std::uint32_t(options_.num_candidates), inv_d_min, inv_d_max,
           float(options_.max_distance)});
    } else {
      filter_.record(seq, guide_, volume_, params);
    }
  }
  if (!finish) {
    seq.end_stage();
    return;
  }
  if (!fused_winner) {
    seq.begin_stage("wta");
    seq.dispatch(wta_kernel_, {volume_.binding(dummy_), distances_[slot].chunks()[0]},
                 WtaPush{std::uint32_t(width_), std::uint32_t(height_),
                         std::uint32_t(options_.num_candidates), inv_d_min, inv_d_max,
                         float(options_.max_distance)},
                 groups);
    seq.barrier();
  }
  if (!options_.post_filter) {
    seq.end_stage();
    return;
  }
  // The filter left a smoothed guide behind: the post-filter starts again from the image.
  seq.begin_stage("post_filter");
  seq.dispatch(guide_kernel_, {images_, guide_}, guide_push, groups);
  seq.barrier();
  post_filter_.record(seq, guide_, distances_[slot],
                      {options_.sigma_i / 2, options_.scaled_sigma_s() / 2});
  seq.end_stage();
}

void DepthEstimator::record(gpu::Sequence& seq) {
  for (std::size_t slot = 0; slot < options_.references.size(); ++slot)
    record_reference(seq, int(slot), true, true);
}

const gpu::Buffer& DepthEstimator::distance_buffer(int slot) const {
  return distances_.at(std::size_t(slot)).chunks()[0];
}

DepthResult DepthEstimator::estimate(const std::vector<const Rgb8Image*>& images) {
  upload_images(images);
  sequence_.begin();
  record(sequence_);
  sequence_.submit_and_wait();
  DepthResult result;
  for (auto& d : distances_) {
    FloatImage map(width_, height_, 1);
    d.chunks()[0].download(map.data(), map.size() * sizeof(float));
    result.distance.push_back(std::move(map));
  }
  result.stage_ms = sequence_.stage_ms();
  return result;
}

Image<std::int32_t> DepthEstimator::selection(int slot) const {
  Image<std::int32_t> out(width_, height_, 1);
  selections_.at(slot).download(out.data(), out.size() * sizeof(std::int32_t));
  return out;
}

std::vector<float> DepthEstimator::cost_volume(const std::vector<const Rgb8Image*>& images,
                                               int slot, bool filtered) {
  upload_images(images);
  sequence_.begin();
  record_reference(sequence_, slot, filtered, false);
  sequence_.submit_and_wait();
  return volume_.download(options_.num_candidates);
}

}  // namespace omnisweep::depth
