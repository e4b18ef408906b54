#include "omnisweep/reproject/forward_warp.h"

#include <cstring>
#include <stdexcept>

namespace omnisweep::reproject {
namespace {

constexpr std::uint32_t kEmpty = 0xffffffffu;

struct InpaintPush {
  std::uint32_t width, height, wrap_x;
};

std::uint64_t pixels(const GpuCamera& c) { return std::uint64_t(c.width) * c.height; }

}  // namespace

ForwardWarper::ForwardWarper(gpu::Context& context, const GpuCamera& source,
                             const GpuCamera& target, const WarpOptions& options)
    : source_(source),
      target_(target),
      options_(options),
      cameras_(context, 2 * sizeof(GpuCamera)),
      directions_(context, pixels(target) * 16),
      buffers_{gpu::Buffer(context, pixels(target) * 4), gpu::Buffer(context, pixels(target) * 4)},
      warp_(context, "forward_warp", {.bindings = {1, 1, 1}}),
      inpaint_(context, "directional_inpaint",
               {.bindings = {1, 1, 1}, .push_constant_bytes = sizeof(InpaintPush)}) {
  if (source.width == 0 || target.width == 0)
    throw std::invalid_argument("forward warp: empty source or target");
  if (!(options.min_distance > 0) || !(options.max_distance > options.min_distance) ||
      options.inpaint_passes < 0) {
    throw std::invalid_argument(
        "forward warp: need 0 < min distance < max distance and inpaint passes >= 0");
  }
  const GpuCamera pair[2] = {source, target};
  cameras_.upload(pair, sizeof(pair));
  const gpu::Kernel directions(context, "inpaint_directions",
                               {.bindings = {1, 1}, .push_constant_bytes = 8});
  gpu::Sequence seq(context, 4, 1);
  seq.begin();
  const float push[2] = {float(options.min_distance), float(options.max_distance)};
  seq.dispatch(directions, {cameras_, directions_}, push, sizeof(push),
               directions.groups_for(target.width, target.height));
  seq.submit_and_wait();
}

void ForwardWarper::record(gpu::Sequence& seq, const gpu::Buffer& distance) {
  if (distance.size() < pixels(source_) * 4) {
    throw std::invalid_argument(
        "forward warp: the distance buffer holds fewer than the source's pixels");
  }
  seq.fill(buffers_[0], kEmpty);
  seq.barrier();
  seq.dispatch(warp_, {cameras_, distance, buffers_[0]}, nullptr, 0,
               warp_.groups_for(source_.width, source_.height));
  seq.barrier();
  const InpaintPush push{target_.width, target_.height, target_.model == 4 ? 1u : 0u};
  for (int pass = 0; pass < options_.inpaint_passes; ++pass) {
    seq.dispatch(inpaint_, {directions_, buffers_[pass % 2], buffers_[(pass + 1) % 2]}, push,
                 inpaint_.groups_for(target_.width, target_.height));
    seq.barrier();
  }
}

const gpu::Buffer& ForwardWarper::result() const { return buffers_[options_.inpaint_passes % 2]; }

FloatImage ForwardWarper::download() const {
  const std::vector<std::uint32_t> bits = result().download<std::uint32_t>();
  FloatImage out(int(target_.width), int(target_.height), 1, 0.0f);
  for (std::size_t i = 0; i < out.size(); ++i) {
    if (bits[i] != kEmpty) std::memcpy(&out.data()[i], &bits[i], 4);
  }
  return out;
}

}  // namespace omnisweep::reproject
