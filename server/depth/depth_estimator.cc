#include "server/depth/depth_estimator.h"

#include <algorithm>
#include <stdexcept>
#include <tuple>

#include "omnisweep/reproject/gpu_camera.h"

namespace omnisweep::depth {
namespace {

using gpu::BindingSlot;

struct SelectionPush {
  std::uint32_t width, height, num_cameras, reference, slot;
  float d_min, d_max;
  std::uint32_t slots;
  float second_power;
};
struct GuidePush {
  std::uint32_t width, height;
  std::uint32_t references[kMaxReferences];
};
struct FeaturesPush {
  std::uint32_t width, height;
  std::int32_t radius, census_radius;
  float epsilon;
  std::uint32_t ratio;
};
struct SweepPush {
  std::uint32_t width, height, num_cameras, first, num_candidates;
  float inv_d_min, inv_d_max, census_scale;
  std::uint32_t slots;
  std::uint32_t references[kMaxReferences];
};
struct WtaPush {
  std::uint32_t width, height, num_candidates;
  float inv_d_min, inv_d_max, d_max;
  std::uint32_t first;
};

struct AgreementPush {
  std::uint32_t width, height, level_width, level_height, num_candidates;
  float inv_d_min, inv_d_max, d_max;
  std::uint32_t first;
  float inv_tolerance;
  std::uint32_t apply;
};
constexpr int kAgreementBlock = 4;  // level-1 pixels per block side (coarse_agreement.comp)

// The coarse agreement's block winners: one float per block of 8 x 8 pixels and slot (16 bytes,
// a placeholder, where it is off).
std::uint64_t agreement_block_bytes(int width, int height, const DepthOptions& options,
                                    std::uint32_t slots) {
  if (options.coarse_agreement <= 0) return 16;
  const int block = 2 * kAgreementBlock;
  return std::uint64_t((width + block - 1) / block) * ((height + block - 1) / block) * slots *
         sizeof(float);
}

// `layout` with the camera kernels' model constants for `rig`'s cameras.
gpu::KernelLayout with_rig_model(gpu::KernelLayout layout, const Rig& rig) {
  const auto models = reproject::model_constants(reproject::common_model(rig));
  layout.constants.insert(layout.constants.end(), models.begin(), models.end());
  return layout;
}

// The sweep's layout: the camera model's constants, the matching cost (constant 30), the
// cameras matched (31) and whether it writes the raw curves' confidence into the guides (32).
gpu::KernelLayout sweep_layout(gpu::KernelLayout layout, const Rig& rig,
                               const DepthOptions& options) {
  layout = with_rig_model(std::move(layout), rig);
  layout.constants.push_back(gpu::SpecConstant::of(30, std::uint32_t(options.cost)));
  layout.constants.push_back(gpu::SpecConstant::of(31, std::uint32_t(options.match_cameras)));
  layout.constants.push_back(
      gpu::SpecConstant::of(32, std::uint32_t(options.confident_sigma_s > 0)));
  return layout;
}

const Rig& checked(const Rig& rig, const DepthOptions& options) {
  options.check(rig.num_cameras());
  rig.check();
  reproject::check_camera_records(options.references.size() * rig.num_cameras());
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

// The volume of as many references per dispatch as fit the device's buffer limits: all of
// them, else the largest group that divides them evenly, down to one at a time.
VolumeLayout plan_group(const gpu::Context& context, const DepthOptions& options) {
  const int references = int(options.references.size());
  const int largest = options.max_group > 0 ? std::min(options.max_group, references) : references;
  for (int group = largest;; --group) {
    if (references % group != 0) continue;
    try {
      return plan_volume(context, options.matching_width, options.matching_height,
                         options.num_candidates, options.half_costs, group);
    } catch (const gpu::GpuError&) {
      if (group == 1) throw;
    }
  }
}

// The cameras of `references` as push constants (unused entries 0).
template <typename Push>
void set_references(Push& push, const std::vector<int>& references) {
  for (std::size_t i = 0; i < references.size(); ++i)
    push.references[i] = std::uint32_t(references[i]);
}

gpu::Texels image_texels(const gpu::Buffer& images) {
  return gpu::Texels(images, gpu::TexelFormat::kR32Uint);
}

}  // namespace

DepthEstimator::DepthEstimator(gpu::Context& context, const Rig& rig,
                               const std::vector<std::optional<Gray8Image>>& usable,
                               const DepthOptions& options)
    : allocated_before_(context.allocated_bytes()),
      options_(options),
      rig_(checked(rig, options)),
      width_(options.matching_width),
      height_(options.matching_height),
      layout_(plan_group(context, options)),
      selection_kernel_(context, gpu::Shader::kCameraSelection,
                        {.bindings = {reproject::camera_binding(), 1, 1},
                         .push_constant_bytes = sizeof(SelectionPush),
                         .constants = reproject::model_constants(reproject::common_model(rig))}),
      guide_kernel_(
          context, gpu::Shader::kYcbcrGuide,
          {.bindings = {BindingSlot::texels(), 1}, .push_constant_bytes = sizeof(GuidePush)}),
      features_kernel_(
          context, gpu::Shader::kMatchingFeatures,
          {.bindings = {BindingSlot::texels(), 1, 1}, .push_constant_bytes = sizeof(FeaturesPush)}),
      sweep_kernel_(context, volume_shader(gpu::Shader::kSphereSweepCost, layout_),
                    sweep_layout(volume_kernel_layout({reproject::camera_binding(),
                                                       BindingSlot::texels(), 1, kMaxChunks, 1},
                                                      sizeof(SweepPush), layout_),
                                 rig, options)),
      wta_kernel_(
          context, volume_shader(gpu::Shader::kWinnerTakeAll, layout_, /*stores=*/false),
          volume_kernel_layout({BindingSlot::texels(kMaxChunks), 1, 1}, sizeof(WtaPush), layout_)),
      agreement_kernel_(context,
                        volume_shader(gpu::Shader::kCoarseAgreement, layout_, /*stores=*/false),
                        volume_kernel_layout({BindingSlot::texels(kMaxChunks), 1, 1, 1},
                                             sizeof(AgreementPush), layout_)),
      volume_(context, width_, height_, layout_),
      filter_(context, width_, height_, layout_, options.confident_sigma_s > 0),
      post_filter_(context, width_, height_, VolumeLayout{1, 1, false, int(slots())},
                   options.confident_sigma_s > 0),
      images_(context, std::uint64_t(width_) * height_ * 4 * rig.num_cameras()),
      blurred_(context, options.match_blur > 0 ? images_.size() : 16),
      features_(context, options.cost == MatchingCost::kAbsoluteDifference
                             ? 16
                             : std::uint64_t(width_) * height_ * 4 * rig.num_cameras()),
      masks_(context, 16),  // the masks below, where the ratio cost reads them
      guide_(context, std::uint64_t(width_) * height_ * 4 * slots()),
      dummy_(context, 16),
      cameras_(context, vk::DeviceSize(slots()) * rig.num_cameras() * sizeof(reproject::GpuCamera)),
      // Per slot its selection plane, then per slot its second cameras' plane.
      selections_(context, std::uint64_t(width_) * height_ * sizeof(std::int32_t) * 2 * slots()),
      distances_(context, width_, height_, VolumeLayout{1, 1, false, int(slots())}),
      confidences_(context, std::uint64_t(width_) * height_ * sizeof(float) * slots()),
      agreement_blocks_(context, agreement_block_bytes(width_, height_, options, slots())),
      sequence_(context) {
  if (options.match_blur > 0)
    blur_.emplace(context, width_, height_, rig.num_cameras(), options.scaled_match_blur());
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

  // Every reference's cameras, then camera selection once per calibration (ALGORITHM.md §3
  // step 2).
  std::vector<reproject::GpuCamera> packed;
  for (const int reference : options.references) {
    const std::vector<reproject::GpuCamera> cameras = reproject::pack_cameras(rig_, reference);
    packed.insert(packed.end(), cameras.begin(), cameras.end());
  }
  cameras_.upload(packed.data(), packed.size() * sizeof(reproject::GpuCamera));
  sequence_.begin();
  for (std::uint32_t slot = 0; slot < slots(); ++slot) {
    sequence_.dispatch(
        selection_kernel_, {cameras_, masks, selections_},
        SelectionPush{std::uint32_t(width_), std::uint32_t(height_),
                      std::uint32_t(rig.num_cameras()), std::uint32_t(options.references[slot]),
                      slot, float(options.min_distance), float(options.max_distance), slots(),
                      float(options.second_camera_power)},
        selection_kernel_.groups_for(width_, height_));
  }
  sequence_.submit_and_wait();
  // The ratio cost's features read the masks every frame; the other costs let them go.
  const vk::DeviceSize transient = ratio_cost() ? 0 : masks.size();
  if (ratio_cost()) masks_ = std::move(masks);
  gpu_bytes_ = context.allocated_bytes() - transient - allocated_before_;
}

std::uint64_t DepthEstimator::gpu_bytes() const { return gpu_bytes_; }

void DepthEstimator::upload_images(std::span<const Rgb8View> images) {
  if (images.size() != std::size_t(rig_.num_cameras())) {
    throw std::invalid_argument("expected " + std::to_string(rig_.num_cameras()) + " images, got " +
                                std::to_string(images.size()));
  }
  const std::size_t pixels = std::size_t(width_) * height_;
  std::vector<std::uint32_t> packed(pixels * images.size());
  for (std::size_t c = 0; c < images.size(); ++c) {
    const Rgb8View& im = images[c];
    if (im.width() != width_ || im.height() != height_) {
      throw std::invalid_argument("image of camera " + std::to_string(c) + " is " +
                                  std::to_string(im.width()) + "x" + std::to_string(im.height()) +
                                  ", expected the matching resolution " + std::to_string(width_) +
                                  "x" + std::to_string(height_));
    }
    reproject::pack_rgba8(im, std::span(packed).subspan(c * pixels, pixels));
  }
  images_.upload(std::span<const std::uint32_t>(packed));
}

void DepthEstimator::record_guides(gpu::Sequence& seq) {
  GuidePush push{std::uint32_t(width_), std::uint32_t(height_), {}};
  set_references(push, options_.references);
  // The ratio cost's features also guide its filters: their edges are the ones it matched, and
  // the shading they normalise away would otherwise set the filter's range weights (on
  // blender-hall MAE 0.049 against 0.063 with the images' guide; docs/accuracy.md).
  seq.dispatch(guide_kernel_, {image_texels(ratio_cost() ? features_ : matched_images()), guide_},
               push, guide_kernel_.groups_for(width_, height_, slots()));
}

void DepthEstimator::record_features(gpu::Sequence& seq) {
  const bool ratio = ratio_cost();
  seq.dispatch(
      features_kernel_, {image_texels(matched_images()), features_, masks_},
      FeaturesPush{std::uint32_t(width_), std::uint32_t(height_),
                   options_.scaled_radius(ratio ? options_.ratio_radius : options_.feature_radius),
                   options_.scaled_radius(options_.census_radius),
                   float(ratio ? options_.ratio_epsilon : options_.feature_epsilon),
                   ratio ? 1u : 0u},
      features_kernel_.groups_for(width_, height_, rig_.num_cameras()));
}

void DepthEstimator::record_group(gpu::Sequence& seq, int first, bool filter, bool finish) {
  const float inv_d_min = float(1.0 / options_.min_distance),
              inv_d_max = float(1.0 / options_.max_distance);
  const auto group = std::uint32_t(group_size());  // groups divide the references evenly
  // Winner takes all in the filter's last pass (the volume is not written back) wherever there
  // is a filter with a last upsample; otherwise its own kernel reads the volume.
  const bool fused_winner = filter && finish && winner_in_filter();

  seq.begin_stage("sweep_cost");
  SweepPush sweep{std::uint32_t(width_),
                  std::uint32_t(height_),
                  std::uint32_t(rig_.num_cameras()),
                  std::uint32_t(first),
                  std::uint32_t(options_.num_candidates),
                  inv_d_min,
                  inv_d_max,
                  float(options_.census_scale),
                  slots(),
                  {}};
  set_references(sweep, options_.references);
  seq.dispatch(sweep_kernel_,
               {cameras_, image_texels(robust_cost() ? features_ : matched_images()), selections_,
                volume_.binding(dummy_), confident_sigma() ? guide_ : dummy_},
               sweep, sweep_kernel_.groups_for(width_, height_, group));
  seq.barrier();
  if (filter) {
    seq.begin_stage("filter");
    const IsbParams params{options_.sigma_i, options_.scaled_sigma_s(),
                           options_.scaled_confident_sigma_s()};
    if (fused_winner) {
      filter_.record_winner_take_all(
          seq, guide_, volume_, params, distances_.chunks()[0], confidences_,
          {std::uint32_t(options_.num_candidates), inv_d_min, inv_d_max,
           float(options_.max_distance),
           options_.raw_agreement > 0 ? float(1.0 / options_.raw_agreement) : 0.0f},
          first, first);
      if (options_.coarse_agreement > 0) record_coarse_agreement(seq, first, false);
    } else {
      filter_.record(seq, guide_, volume_, params, first);
    }
  }
  if (!finish || fused_winner) return;
  seq.begin_stage("wta");
  seq.dispatch(
      wta_kernel_, {volume_.texels(dummy_), distances_.chunks()[0], confidences_},
      WtaPush{std::uint32_t(width_), std::uint32_t(height_), std::uint32_t(options_.num_candidates),
              inv_d_min, inv_d_max, float(options_.max_distance), std::uint32_t(first)},
      wta_kernel_.groups_for(width_, height_, group));
  seq.barrier();
}

std::vector<float> DepthEstimator::filter_level_costs(int slot_in_group, int* width,
                                                      int* height) const {
  std::tie(*width, *height) = filter_.level_size(1);
  return filter_.level_volume(1).download(options_.num_candidates, slot_in_group);
}

void DepthEstimator::record_coarse_agreement(gpu::Sequence& seq, int first, bool apply) {
  const auto [level_width, level_height] = filter_.level_size(1);
  const int blocks_x = (level_width + kAgreementBlock - 1) / kAgreementBlock;
  const int blocks_y = (level_height + kAgreementBlock - 1) / kAgreementBlock;
  // Each pass binds only what it reads or writes (the cost model counts what is bound): the
  // level's costs for the winners, the distances and confidences for the factor.
  const gpu::Texels level = apply
                                ? gpu::Texels(std::vector<const gpu::Buffer*>(kMaxChunks, &dummy_),
                                              layout_.texel_format())
                                : filter_.level_volume(1).texels(dummy_);
  seq.dispatch(
      agreement_kernel_,
      {level, apply ? distances_.chunks()[0] : dummy_, apply ? confidences_ : dummy_,
       agreement_blocks_},
      AgreementPush{std::uint32_t(width_), std::uint32_t(height_), std::uint32_t(level_width),
                    std::uint32_t(level_height), std::uint32_t(options_.num_candidates),
                    float(1.0 / options_.min_distance), float(1.0 / options_.max_distance),
                    float(options_.max_distance), std::uint32_t(first),
                    float(1.0 / options_.coarse_agreement), std::uint32_t(apply)},
      agreement_kernel_.groups_for(blocks_x, blocks_y,
                                   apply ? slots() : std::uint32_t(group_size())));
  seq.barrier();
}

void DepthEstimator::record_post_filter(gpu::Sequence& seq) {
  seq.begin_stage("post_filter");
  // A filter whose last pass was not the fused winner left smoothed guides behind: start again
  // from the images.
  if (!winner_in_filter()) {
    record_guides(seq);
    seq.barrier();
  }
  post_filter_.record(seq, guide_, distances_,
                      {options_.sigma_i / 2, options_.scaled_sigma_s() / 2,
                       options_.scaled_confident_sigma_s() / 2});
}

void DepthEstimator::record_blur(gpu::Sequence& seq) {
  if (!blur_) return;
  seq.begin_stage("match_blur");
  blur_->record(seq, images_, blurred_);
  seq.barrier();
}

void DepthEstimator::record(gpu::Sequence& seq) {
  record_blur(seq);
  seq.begin_stage("filter");
  if (robust_cost()) {  // the sweep's input (and the ratio's guides)
    record_features(seq);
    seq.barrier();
  }
  record_guides(seq);  // independent of the sweep: the sweep's barrier covers both
  if (confident_sigma()) seq.barrier();  // unless the sweep writes into them
  for (int first = 0; first < int(slots()); first += group_size())
    record_group(seq, first, true, true);
  if (options_.post_filter) record_post_filter(seq);
  if (options_.coarse_agreement > 0 && winner_in_filter()) {
    seq.barrier();
    record_coarse_agreement(seq, 0, true);  // on the final distances
  }
  seq.end_stage();
}

std::vector<std::uint32_t> DepthEstimator::matching_features(int camera) const {
  if (!robust_cost()) throw std::logic_error("the paper's cost computes no matching features");
  if (camera < 0 || camera >= rig_.num_cameras()) throw std::out_of_range("no such camera");
  std::vector<std::uint32_t> out(std::size_t(width_) * height_);
  features_.download(out.data(), out.size() * 4, std::size_t(camera) * out.size() * 4);
  return out;
}

const gpu::Buffer& DepthEstimator::distance_buffer() const { return distances_.chunks()[0]; }

DepthResult DepthEstimator::estimate(std::span<const Rgb8View> images) {
  upload_images(images);
  sequence_.begin();
  record(sequence_);
  sequence_.submit_and_wait();
  DepthResult result;
  const std::size_t bytes = std::size_t(width_) * height_ * sizeof(float);
  for (std::uint32_t slot = 0; slot < slots(); ++slot) {
    FloatImage map(width_, height_);
    distance_buffer().download(map.data(), bytes, slot * bytes);
    result.distance.push_back(std::move(map));
    FloatImage confidence(width_, height_);
    confidences_.download(confidence.data(), bytes, slot * bytes);
    result.confidence.push_back(std::move(confidence));
  }
  result.stage_ms = sequence_.stage_ms();
  return result;
}

Image<std::int32_t> DepthEstimator::selection(int slot) const {
  if (slot < 0 || slot >= int(slots())) throw std::out_of_range("no such reference slot");
  Image<std::int32_t> out(width_, height_);
  const std::size_t bytes = out.size() * sizeof(std::int32_t);
  selections_.download(out.data(), bytes, std::size_t(slot) * bytes);
  return out;
}

Image<std::int32_t> DepthEstimator::second_selection(int slot) const {
  if (slot < 0 || slot >= int(slots())) throw std::out_of_range("no such reference slot");
  Image<std::int32_t> out(width_, height_);
  const std::size_t bytes = out.size() * sizeof(std::int32_t);
  selections_.download(out.data(), bytes, (std::size_t(slots()) + slot) * bytes);
  return out;
}

std::vector<float> DepthEstimator::cost_volume(std::span<const Rgb8View> images, int slot,
                                               bool filtered) {
  if (slot < 0 || slot >= int(slots())) throw std::out_of_range("no such reference slot");
  upload_images(images);
  const int first = slot / group_size() * group_size();
  sequence_.begin();
  record_blur(sequence_);
  if (robust_cost()) {
    record_features(sequence_);
    sequence_.barrier();
  }
  if (filtered) {
    record_guides(sequence_);
    if (confident_sigma()) sequence_.barrier();  // the sweep writes into the guides
  }
  record_group(sequence_, first, filtered, false);
  sequence_.submit_and_wait();
  return volume_.download(options_.num_candidates, slot - first);
}

}  // namespace omnisweep::depth
