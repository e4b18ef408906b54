#include "server/stitch/temporal_filter.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "omnisweep/reproject/forward_warp.h"
#include "omnisweep/reproject/gpu_camera.h"
#include "server/stitch/same_size.h"

namespace omnisweep::stitch {
namespace {

struct ChangesPush {
  std::uint32_t width, height;
  float threshold;
};

struct FilterPush {
  std::uint32_t width, height;
  float threshold, jump, max_frames;
  std::uint32_t reset_pixels, first;
  float confident;
};

std::uint32_t reset_pixels(std::size_t pixels, double share) {
  return std::uint32_t(std::floor(double(pixels) * share));
}

float color_moved(std::uint32_t a, std::uint32_t b) {
  float sum = 0;
  for (int c = 0; c < 3; ++c)
    sum += std::abs(float((a >> (8 * c)) & 255u) - float((b >> (8 * c)) & 255u));
  return sum;
}

}  // namespace

void TemporalOptions::check() const {
  if (max_frames < 1 || max_frames > 1000)
    throw reproject::option_error("TemporalOptions", "max_frames", max_frames, "1-1000");
  if (!(jump > 0) || !std::isfinite(jump))
    throw reproject::option_error("TemporalOptions", "jump", jump, "a positive number (1/m)");
  if (!(color_threshold >= 0) || !(color_threshold <= 765)) {
    throw reproject::option_error("TemporalOptions", "colour_threshold", color_threshold,
                                  "0-765 (8-bit levels over R, G and B)");
  }
  if (!(reset_share >= 0 && reset_share <= 1))
    throw reproject::option_error("TemporalOptions", "reset_share", reset_share, "0-1");
  if (!(confident >= 0 && confident <= 1))
    throw reproject::option_error("TemporalOptions", "confident", confident, "0-1");
}

void temporal_filter_cpu(TemporalState& state, FloatImage& distance, const Rgb8Image& color,
                         const FloatImage& confidence, const TemporalOptions& options) {
  options.check();
  const std::size_t n = distance.size();
  require_same_size("temporal filter", {sized("distance", distance), sized("colour", color),
                                        sized("confidence", confidence)});
  std::vector<std::uint32_t> packed(n);  // as the kernels read colour (alpha is not compared)
  reproject::pack_rgba8(color, packed);
  if (state.mean_inverse.size() != n) {
    state = {std::vector<float>(n, 0.0f), std::vector<float>(n, 0.0f),
             std::vector<std::uint32_t>(n, 0u), std::vector<float>(n, 0.0f), false};
  }
  const auto threshold = float(options.color_threshold);
  std::uint32_t changed = 0;
  for (std::size_t i = 0; i < n; ++i)
    changed += color_moved(packed[i], state.previous_color[i]) > threshold;
  const bool reset_all = !state.started || changed > reset_pixels(n, options.reset_share);
  const auto jump = float(options.jump), max_frames = float(options.max_frames);
  const auto confident = float(options.confident);
  for (std::size_t i = 0; i < n; ++i) {
    const float d = distance.data()[i];
    const float z = d > 0.0f ? 1.0f / d : 0.0f;
    float x = state.mean_inverse[i], count = state.count[i];
    bool restart = reset_all || color_moved(packed[i], state.previous_color[i]) > threshold ||
                   !(z > 0) || !(x > 0);
    float pending = 0.0f;
    if (!restart && std::abs(z - x) >= jump) {
      const float earlier = state.pending_inverse[i];
      if (confidence.data()[i] >= confident || (earlier > 0 && std::abs(z - earlier) < jump))
        restart = true;
      else
        pending = z;
    }
    if (restart) {
      x = z;
      count = 1.0f;
    } else {
      count = std::min(count + 1.0f, max_frames);
      x += (z - x) / count;
    }
    state.pending_inverse[i] = pending;
    state.mean_inverse[i] = x;
    state.count[i] = count;
    state.previous_color[i] = packed[i];
    distance.data()[i] = x > 0.0f ? 1.0f / x : 0.0f;
  }
  state.started = true;
}

TemporalFilter::TemporalFilter(gpu::Context& context, int width, int height,
                               const TemporalOptions& options)
    : options_((options.check(), options)),
      width_(std::uint32_t(width)),
      height_(std::uint32_t(height)),
      pixels_(width_ * height_),
      mean_inverse_(context, std::uint64_t(pixels_) * 4),
      count_(context, std::uint64_t(pixels_) * 4),
      previous_color_(context, std::uint64_t(pixels_) * 4),
      pending_inverse_(context, std::uint64_t(pixels_) * 4),
      changed_(context, 16),
      changes_(context, gpu::Shader::kTemporalChanges,
               {.bindings = {1, 1, 1}, .push_constant_bytes = sizeof(ChangesPush)}),
      filter_(context, gpu::Shader::kTemporalFilter,
              {.bindings = {1, 1, 1, 1, 1, 1, 1, 1}, .push_constant_bytes = sizeof(FilterPush)}) {}

void TemporalFilter::record(gpu::Sequence& seq, gpu::Buffer& distance, const gpu::Buffer& color,
                            const gpu::Buffer& confidence) {
  const std::uint64_t bytes = std::uint64_t(pixels_) * 4;
  if (distance.size() < bytes || color.size() < bytes || confidence.size() < bytes)
    throw std::invalid_argument("temporal filter: the panorama buffers are smaller than its size");
  const auto threshold = float(options_.color_threshold);
  seq.begin_stage("temporal");
  seq.fill(changed_, 0u);
  seq.barrier();
  seq.dispatch(changes_, {color, previous_color_, changed_},
               ChangesPush{width_, height_, threshold}, changes_.groups_for(width_, height_));
  seq.barrier();
  seq.dispatch(filter_,
               {distance, color, mean_inverse_, count_, previous_color_, changed_, confidence,
                pending_inverse_},
               FilterPush{width_, height_, threshold, float(options_.jump),
                          float(options_.max_frames), reset_pixels(pixels_, options_.reset_share),
                          started_ ? 0u : 1u, float(options_.confident)},
               filter_.groups_for(width_, height_));
  seq.barrier();
  started_ = true;
}

}  // namespace omnisweep::stitch
