#include "server/depth/isb_filter.h"

#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

#include "omnisweep/reproject/forward_warp.h"

namespace omnisweep::depth {
namespace {

struct DownPush {
  std::uint32_t fine_width, fine_height, coarse_width, coarse_height;
  float inv_two_sigma_sq;
  std::uint32_t fine_guide_first;
};

struct UpPush {
  std::uint32_t fine_width, fine_height, coarse_width, coarse_height;
  float inv_two_sigma_sq;
  float w_down;
  std::uint32_t fine_guide_first;
  WtaParams wta;  // read by the kWinnerTakesAll variant only
  std::uint32_t distance_first;
  float scale_sq, sigma_s, sigma_confident;  // read with kConfidentSigma only
};

using gpu::BindingSlot;

gpu::KernelLayout down_layout(VolumeLayout layout, bool confident_sigma) {
  gpu::KernelLayout k =
      volume_kernel_layout({BindingSlot::texels(), 1, BindingSlot::texels(kMaxChunks), kMaxChunks},
                           sizeof(DownPush), layout);
  k.constants.push_back(gpu::SpecConstant::of(3, std::uint32_t(confident_sigma)));
  return k;
}

// Bindings: the fine guide and volume are written as storage buffers (0, 2) and read as texel
// buffers (5, 6) of the same memory; the coarse level is read only; the fused winner writes
// distances (4) and confidences (7).
gpu::KernelLayout up_layout(VolumeLayout layout, bool winner_take_all, bool confident_sigma) {
  gpu::KernelLayout k =
      volume_kernel_layout({1, BindingSlot::texels(), kMaxChunks, BindingSlot::texels(kMaxChunks),
                            1, BindingSlot::texels(), BindingSlot::texels(kMaxChunks), 1},
                           sizeof(UpPush), layout);
  k.constants.push_back(gpu::SpecConstant::of(2, std::uint32_t(winner_take_all)));
  k.constants.push_back(gpu::SpecConstant::of(3, std::uint32_t(confident_sigma)));
  return k;
}

gpu::Texels guide_texels(const gpu::Buffer& guide) {
  return gpu::Texels(guide, gpu::TexelFormat::kR32Uint);
}

}  // namespace

int isb_levels(int width, int height) {
  const int log2_min = int(std::floor(std::log2(double(std::min(width, height)))));
  return std::max(1, log2_min - 1);
}

IsbFilter::IsbFilter(gpu::Context& context, int width, int height, VolumeLayout layout,
                     bool confident_sigma)
    : context_(&context),
      layout_(layout),
      confident_sigma_(confident_sigma),
      dummy_(context, 16),
      down_(context, volume_shader(gpu::Shader::kIsbDownsample, layout),
            down_layout(layout, confident_sigma)),
      up_(context, volume_shader(gpu::Shader::kIsbUpsample, layout),
          up_layout(layout, false, confident_sigma)),
      up_wta_(context, volume_shader(gpu::Shader::kIsbUpsample, layout),
              up_layout(layout, true, confident_sigma)) {
  if (!context.info().buffer_array_indexing) {
    throw gpu::GpuError(context.info().name +
                        " lacks shaderStorageBufferArrayDynamicIndexing, which the filter needs");
  }
  sizes_.emplace_back(width, height);
  for (int l = 1; l < isb_levels(width, height); ++l) {
    const auto [w, h] = sizes_.back();
    sizes_.emplace_back((w + 1) / 2, (h + 1) / 2);
    guides_.emplace_back(
        context, std::uint64_t(sizes_.back().first) * sizes_.back().second * 4 * layout.slots);
    volumes_.emplace_back(context, sizes_.back().first, sizes_.back().second, layout);
  }
}

std::uint64_t IsbFilter::bytes() const {
  std::uint64_t total = dummy_.size();
  for (const auto& g : guides_) total += g.size();
  for (const auto& v : volumes_) total += v.bytes();
  return total;
}

void IsbFilter::record(gpu::Sequence& seq, gpu::Buffer& guide, CostVolume& volume,
                       const IsbParams& params, int guide_first) {
  record(seq, guide, volume, params, nullptr, nullptr, {}, guide_first, 0);
}

void IsbFilter::record_winner_take_all(gpu::Sequence& seq, gpu::Buffer& guide, CostVolume& volume,
                                       const IsbParams& params, gpu::Buffer& distance,
                                       gpu::Buffer& confidence, const WtaParams& wta,
                                       int guide_first, int distance_first) {
  if (levels() < 2) throw std::invalid_argument("ISB filter: a fused winner needs 2 levels");
  record(seq, guide, volume, params, &distance, &confidence, wta, guide_first, distance_first);
}

void IsbParams::check() const {
  if (!(sigma_i > 0) || !std::isfinite(sigma_i))
    throw reproject::option_error("IsbParams", "sigma_i", sigma_i, "a positive number");
  if (!(sigma_s > 0) || !std::isfinite(sigma_s))
    throw reproject::option_error("IsbParams", "sigma_s", sigma_s, "a positive number");
  if (!(sigma_s_confident >= 0) || !std::isfinite(sigma_s_confident))
    throw reproject::option_error("IsbParams", "sigma_s_confident", sigma_s_confident,
                                  "0 or a positive number");
}

void IsbFilter::record(gpu::Sequence& seq, gpu::Buffer& guide, CostVolume& volume,
                       const IsbParams& params, gpu::Buffer* distance, gpu::Buffer* confidence,
                       const WtaParams& wta, int guide_first, int distance_first) {
  params.check();
  if (confident_sigma_ != (params.sigma_s_confident > 0)) {
    throw std::invalid_argument(
        confident_sigma_ ? "ISB filter: made for a confident sigma, but sigma_s_confident is 0"
                         : "ISB filter: sigma_s_confident needs a filter made for it");
  }
  if (volume.layout().slots != layout_.slots)
    throw std::invalid_argument("ISB filter: the volume's slots differ from the filter's");
  if (guide_first < 0 || distance_first < 0)
    throw std::invalid_argument("ISB filter: negative guide or distance plane");
  const auto slots = std::uint32_t(layout_.slots);
  const float inv_two_sigma_sq = float(1.0 / (2.0 * params.sigma_i * params.sigma_i));
  auto guide_at = [&](int l) -> gpu::Buffer& { return l == 0 ? guide : guides_[l - 1]; };
  auto volume_at = [&](int l) -> CostVolume& { return l == 0 ? volume : volumes_[l - 1]; };
  for (int l = 0; l + 1 < levels(); ++l) {  // down: level l -> l + 1
    const auto [fw, fh] = sizes_[l];
    const auto [cw, ch] = sizes_[l + 1];
    seq.dispatch(
        down_,
        {guide_texels(guide_at(l)), guide_at(l + 1), volume_at(l).texels(dummy_),
         volume_at(l + 1).binding(dummy_)},
        DownPush{std::uint32_t(fw), std::uint32_t(fh), std::uint32_t(cw), std::uint32_t(ch),
                 inv_two_sigma_sq, std::uint32_t(l == 0 ? guide_first : 0)},
        down_.groups_for(cw, ch, slots));
    seq.barrier();
  }
  for (int l = levels() - 2; l >= 0; --l) {  // up: level l + 1 -> l
    const auto [fw, fh] = sizes_[l];
    const auto [cw, ch] = sizes_[l + 1];
    const double scale = std::ldexp(1.0, l) - 0.5;
    const float w_down = float(std::exp(-scale * scale / (2.0 * params.sigma_s * params.sigma_s)));
    const bool fused = distance && l == 0;
    seq.dispatch(
        fused ? up_wta_ : up_,
        {guide_at(l), guide_texels(guide_at(l + 1)), volume_at(l).binding(dummy_),
         volume_at(l + 1).texels(dummy_), fused ? *distance : dummy_, guide_texels(guide_at(l)),
         volume_at(l).texels(dummy_), fused ? *confidence : dummy_},
        UpPush{std::uint32_t(fw), std::uint32_t(fh), std::uint32_t(cw), std::uint32_t(ch),
               inv_two_sigma_sq, w_down, std::uint32_t(l == 0 ? guide_first : 0),
               fused ? wta : WtaParams{}, std::uint32_t(distance_first), float(scale * scale),
               float(params.sigma_s), float(params.sigma_s_confident)},
        up_.groups_for(cw, ch, slots));  // one invocation per coarse pixel
    seq.barrier();
  }
}

}  // namespace omnisweep::depth
