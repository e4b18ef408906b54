// The inter-scale bilateral (ISB) filter on the GPU (paper §3.2.1, ALGORITHM.md §4): a guided
// edge-aware filter that builds a pyramid with guided 3x3 downsampling and then blends each
// level back into the finer one, guided by already smoothed guides. Work is a geometric series,
// so time is linear in pixels. Every channel of a volume shares the guide's weights, so all
// channels of a pixel are filtered by one invocation.
#pragma once

#include <vector>

#include "omnisweep/gpu/kernel.h"
#include "omnisweep/gpu/sequence.h"
#include "server/depth/cost_volume.h"

namespace omnisweep::depth {

struct IsbParams {
  double sigma_i = 10.0;  // range sigma, 8-bit guide units
  double sigma_s = 25.0;  // spatial sigma in pixels of this resolution
  // With a filter made for it: where the guide's fourth byte (the raw cost curves' confidence,
  // 255 = 1) is at least 0.5, the spatial sigma falls linearly to this at 0.7 (isb_weights.glsl,
  // DepthOptions::confident_sigma_s); 0 with any other filter.
  double sigma_s_confident = 0;
  // Throws std::invalid_argument naming the field, its value and what is allowed.
  void check() const;
};

// Winner takes all fused into the filter's last pass (wta.glsl): the candidates' spacing.
struct WtaParams {
  std::uint32_t num_candidates = 32;
  float inv_d_min = 0, inv_d_max = 0, d_max = 0;
  // 1 / DepthOptions::raw_agreement: the confidence's factor from the raw curve at the filtered
  // winner (wta.glsl, raw_agreement_cpu); 0: off.
  float inv_raw_agreement = 0;
};

// L = floor(min(log2 W, log2 H)) - 1 levels including full resolution (at least 1).
int isb_levels(int width, int height);

class IsbFilter {
 public:
  // A filter for width x height volumes with `layout` (every slot of it in each dispatch);
  // allocates the coarser levels. `confident_sigma`: its guides carry the raw curves'
  // confidence in their fourth byte, and IsbParams::sigma_s_confident applies (then > 0).
  IsbFilter(gpu::Context& context, int width, int height, VolumeLayout layout,
            bool confident_sigma = false);

  // Records the filter into `seq`: `volume` (full resolution) is filtered in place; `guide`
  // (packed 8-bit, 3 channels, a width x height plane per slot from plane `guide_first` on; a
  // filter made for a confident sigma also reads the fourth byte) is consumed: it ends up
  // holding the smoothed guides.
  void record(gpu::Sequence& seq, gpu::Buffer& guide, CostVolume& volume, const IsbParams& params,
              int guide_first = 0);
  // The same, ending in winner-takes-all: the last pass writes each pixel's winning distance to
  // `distance` and the confidence of its cost curve (wta.glsl) to `confidence` (width x height
  // floats per slot each, from plane `distance_first` on) instead of the filtered costs, so
  // `volume` is left holding intermediate values and `guide` is not updated by that pass. Needs
  // at least 2 levels.
  void record_winner_take_all(gpu::Sequence& seq, gpu::Buffer& guide, CostVolume& volume,
                              const IsbParams& params, gpu::Buffer& distance,
                              gpu::Buffer& confidence, const WtaParams& wta, int guide_first = 0,
                              int distance_first = 0);

  int levels() const { return int(sizes_.size()); }
  // Level l >= 1 as the last record() left it (filtered, in the volume's layout), and its size.
  const CostVolume& level_volume(int l) const { return volumes_.at(std::size_t(l) - 1); }
  std::pair<int, int> level_size(int l) const { return sizes_.at(std::size_t(l)); }
  std::uint64_t bytes() const;

 private:
  void record(gpu::Sequence& seq, gpu::Buffer& guide, CostVolume& volume, const IsbParams& params,
              gpu::Buffer* distance, gpu::Buffer* confidence, const WtaParams& wta, int guide_first,
              int distance_first);

  gpu::Context* context_;
  VolumeLayout layout_;
  bool confident_sigma_;
  std::vector<std::pair<int, int>> sizes_;  // per level
  std::vector<gpu::Buffer> guides_;         // levels 1..L-1
  std::vector<CostVolume> volumes_;         // levels 1..L-1
  gpu::Buffer dummy_;
  gpu::Kernel down_;
  gpu::Kernel up_;
  gpu::Kernel up_wta_;  // isb_upsample with kWinnerTakesAll
};

}  // namespace omnisweep::depth
