#include "omnisweep/reproject/forward_warp.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>

namespace omnisweep::reproject {
namespace {

constexpr std::uint32_t kEmpty = 0xffffffffu;

constexpr int kMaxPasses = 1024;

struct InpaintPush {
  std::uint32_t width, height, wrap_x, pass, passes;
  std::uint32_t status_set;  // alternates from dispatch to dispatch, as *current does
};

// Passes one inpainting dispatch runs (kHalo in shaders/include/inpaint_tile.glsl), its
// workgroup shape, and the tile side that fits a device's shared memory: two uints per pixel of
// the tile and its halo.
constexpr int kPassesPerDispatch = 8;
constexpr std::uint32_t kInpaintGroup = 16;
std::uint32_t inpaint_tile(const gpu::Context& context) {
  const auto fits = [&](std::uint32_t tile) {
    const std::uint64_t side = tile + 2 * kPassesPerDispatch;
    return side * side * 8 <= context.info().max_shared_memory;
  };
  return fits(32) ? 32 : 16;
}

gpu::KernelLayout inpaint_layout(std::uint32_t tile) {
  return {.bindings = {gpu::BindingSlot::texels(), gpu::BindingSlot::texels(), 1, 1, 1},
          .storage_images = 0,
          .push_constant_bytes = sizeof(InpaintPush),
          .local_size = {kInpaintGroup, kInpaintGroup, 1},
          .constants = {gpu::SpecConstant::of(0, tile)}};
}

std::uint64_t pixels(const GpuCamera& c) { return std::uint64_t(c.width) * c.height; }

// The model every layer's source (or target) has, or kAny.
GpuModel layers_model(const std::vector<WarpLayer>& layers, bool target) {
  std::vector<GpuCamera> cameras;
  cameras.reserve(layers.size());
  for (const WarpLayer& l : layers) cameras.push_back(target ? l.target : l.source);
  return common_model(cameras);
}

// A kernel that projects, compiled for the layers' source and target camera models.
gpu::Kernel camera_kernel(const gpu::Context& context, gpu::Shader shader,
                          std::vector<gpu::BindingSlot> bindings, std::uint32_t push_bytes,
                          const std::vector<WarpLayer>& layers) {
  return gpu::Kernel(
      context, shader,
      {.bindings = std::move(bindings),
       .push_constant_bytes = push_bytes,
       .constants = model_constants(layers_model(layers, false), layers_model(layers, true))});
}
gpu::Kernel warp_kernel(const gpu::Context& context, const std::vector<WarpLayer>& layers) {
  return camera_kernel(context, gpu::Shader::kForwardWarp,
                       {camera_binding(), gpu::BindingSlot::texels(), 1}, 4, layers);
}
gpu::Kernel directions_kernel(const gpu::Context& context, const std::vector<WarpLayer>& layers) {
  return camera_kernel(context, gpu::Shader::kInpaintDirections, {camera_binding(), 1}, 8, layers);
}
gpu::Kernel sample_color_kernel(const gpu::Context& context, const std::vector<WarpLayer>& layers) {
  return camera_kernel(context, gpu::Shader::kSampleViewColor,
                       {camera_binding(), gpu::BindingSlot::texels(), gpu::BindingSlot::texels(),
                        gpu::BindingSlot::texels(), 1},
                       4, layers);
}

std::vector<WarpLayer> checked(std::vector<WarpLayer> layers, const WarpOptions& options) {
  options.check();
  const bool color = options.color;
  if (layers.empty()) throw std::invalid_argument("forward warp: no layers");
  for (const WarpLayer& l : layers) {
    if (l.source.width == 0 || l.target.width == 0)
      throw std::invalid_argument("forward warp: empty source or target");
    if (l.source.width != layers[0].source.width || l.source.height != layers[0].source.height ||
        l.target.width != layers[0].target.width || l.target.height != layers[0].target.height) {
      throw std::invalid_argument("forward warp: layers must share one source and one target size");
    }
  }
  if (color && layers.size() > 1)
    throw std::invalid_argument("forward warp: colour needs a warper of one layer");
  check_camera_records(2 * layers.size());
  return layers;
}

}  // namespace

void check_warp_range(std::string_view owner, double min_distance, double max_distance,
                      int inpaint_passes) {
  if (!(min_distance > 0) || !std::isfinite(min_distance))
    throw option_error(owner, "min_distance", min_distance, "a positive number of metres");
  if (!(max_distance > min_distance) || !std::isfinite(max_distance))
    throw option_error(owner, "max_distance", max_distance, "finite and larger than min_distance");
  if (inpaint_passes < 0 || inpaint_passes > 1024)
    throw option_error(owner, "inpaint_passes", inpaint_passes, "within [0, 1024]");
}

void WarpOptions::check() const {
  check_warp_range("WarpOptions", min_distance, max_distance, inpaint_passes);
  if (!(max_splat >= 1.0) || !std::isfinite(max_splat))
    throw option_error("WarpOptions", "max_splat", max_splat, "at least 1 (pixels across)");
  if (!(occlusion_tolerance >= 0 && occlusion_tolerance < 1))
    throw option_error("WarpOptions", "occlusion_tolerance", occlusion_tolerance, "within [0, 1)");
}

ForwardWarper::ForwardWarper(gpu::Context& context, const GpuCamera& source,
                             const GpuCamera& target, const WarpOptions& options)
    : ForwardWarper(context, std::vector<WarpLayer>{{source, target}}, options) {}

ForwardWarper::ForwardWarper(gpu::Context& context, std::vector<WarpLayer> layers,
                             const WarpOptions& options)
    : context_(&context),
      layers_(checked(std::move(layers), options)),
      options_(options),
      cameras_(context, 2 * layers_.size() * sizeof(GpuCamera)),
      directions_(context, layers_.size() * pixels(target()) * 16),
      buffers_{gpu::Buffer(context, layers_.size() * pixels(target()) * 4),
               gpu::Buffer(context, layers_.size() * pixels(target()) * 4)},
      filled_(context, vk::DeviceSize(kMaxPasses) * 4),
      tile_(inpaint_tile(context)),
      tile_status_(context, std::uint64_t((target().width + tile_ - 1) / tile_) *
                                ((target().height + tile_ - 1) / tile_) * layers_.size() * 2 * 4),
      warp_(warp_kernel(context, layers_)),
      directions_kernel_(directions_kernel(context, layers_)),
      inpaint_(context, gpu::Shader::kDirectionalInpaint, inpaint_layout(tile_)) {
  if (!(options.min_distance > 0) || !(options.max_distance > options.min_distance) ||
      options.inpaint_passes < 0 || options.inpaint_passes > kMaxPasses ||
      !(options.max_splat >= 1.0) ||
      !(options.occlusion_tolerance >= 0 && options.occlusion_tolerance < 1)) {
    throw std::invalid_argument(
        "forward warp: need 0 < min distance < max distance, inpaint passes in [0, 1024], max "
        "splat >= 1 and 0 <= occlusion tolerance < 1");
  }
  if (options.color) {
    color_buffers_.emplace_back(context, pixels(target()) * 4);
    color_buffers_.emplace_back(context, pixels(target()) * 4);
    sample_color_.emplace(sample_color_kernel(context, layers_));
    inpaint_color_.emplace(context, gpu::Shader::kDirectionalInpaintColor, inpaint_layout(tile_));
  }
  upload_cameras();
}

void ForwardWarper::upload_cameras() {
  std::vector<GpuCamera> pairs;  // source, target of each layer
  for (const WarpLayer& l : layers_) {
    pairs.push_back(l.source);
    pairs.push_back(l.target);
  }
  cameras_.upload(pairs.data(), pairs.size() * sizeof(GpuCamera));
  directions_stale_ = true;
}

void ForwardWarper::set_target(const GpuCamera& target) {
  if (layers_.size() != 1)
    throw std::logic_error("forward warp: set_target needs a warper of one layer");
  if (target.width != this->target().width || target.height != this->target().height)
    throw std::invalid_argument("forward warp: set_target must keep the target's size");
  const bool recompile = target.model != this->target().model;
  layers_[0].target = target;
  if (recompile) {  // the kernels were compiled for the other model
    warp_ = warp_kernel(*context_, layers_);
    directions_kernel_ = directions_kernel(*context_, layers_);
    if (sample_color_) sample_color_.emplace(sample_color_kernel(*context_, layers_));
  }
  upload_cameras();
}

void ForwardWarper::set_inpaint_passes(int passes) {
  if (passes < 0 || passes > kMaxPasses)
    throw std::invalid_argument("forward warp: inpaint passes must lie in [0, 1024]");
  options_.inpaint_passes = passes;
}

void ForwardWarper::record_inpaint(gpu::Sequence& seq, const gpu::Kernel& kernel,
                                   gpu::Buffer* buffers, int first_pass, int passes,
                                   int* current) const {
  const GpuCamera& t = target();
  const std::array<std::uint32_t, 3> groups = {
      (t.width + tile_ - 1) / tile_, (t.height + tile_ - 1) / tile_, std::uint32_t(layers_.size())};
  const std::uint32_t wrap_x = t.model == std::uint32_t(GpuModel::kEquirectangular) ? 1u : 0u;
  for (int pass = first_pass; pass < first_pass + passes; pass += kPassesPerDispatch) {
    const int n = std::min(kPassesPerDispatch, first_pass + passes - pass);
    const InpaintPush push{
        t.width, t.height, wrap_x, std::uint32_t(pass), std::uint32_t(n), std::uint32_t(*current)};
    seq.dispatch(kernel,
                 {gpu::Texels(directions_, gpu::TexelFormat::kRgba32Uint),
                  gpu::Texels(buffers[*current], gpu::TexelFormat::kR32Uint), buffers[1 - *current],
                  filled_, tile_status_},
                 push, groups);
    seq.barrier();
    *current = 1 - *current;
  }
}

void ForwardWarper::record_warp(gpu::Sequence& seq, const gpu::Buffer& distance) {
  const auto count = std::uint32_t(layers_.size());
  if (distance.size() < count * pixels(source()) * 4) {
    throw std::invalid_argument(
        "forward warp: the distance buffer holds fewer than the sources' pixels");
  }
  if (directions_stale_) {
    const float push[2] = {float(options_.min_distance), float(options_.max_distance)};
    seq.dispatch(directions_kernel_, {cameras_, directions_}, push, sizeof(push),
                 directions_kernel_.groups_for(target().width, target().height, count));
    directions_stale_ = false;
  }
  seq.fill(buffers_[0], kEmpty);
  seq.barrier();
  const float splat = float(options_.max_splat);
  seq.dispatch(warp_, {cameras_, gpu::Texels(distance, gpu::TexelFormat::kR32Float), buffers_[0]},
               splat, warp_.groups_for(source().width, source().height, count));
  seq.barrier();
  result_ = 0;
}

void ForwardWarper::record(gpu::Sequence& seq, const gpu::Buffer& distance) {
  record_warp(seq, distance);
  record_inpaint(seq, inpaint_, buffers_, 0, options_.inpaint_passes, &result_);
}

int ForwardWarper::run_until_filled(gpu::Sequence& seq, const gpu::Kernel& kernel,
                                    gpu::Buffer* buffers, int max_passes, int batch, double* gpu_ms,
                                    int* current) {
  if (max_passes < 0 || max_passes > kMaxPasses || batch < 1)
    throw std::invalid_argument("forward warp: need max passes in [0, 1024] and batch >= 1");
  seq.fill(filled_, 0);
  seq.barrier();
  int done = 0;
  for (;;) {
    const int n = std::min(batch, max_passes - done);
    record_inpaint(seq, kernel, buffers, done, n, current);
    seq.submit_and_wait();
    for (const auto& [stage, ms] : seq.stage_ms()) *gpu_ms += ms;
    done += n;
    if (done >= max_passes) return done;
    std::uint32_t last = 1;
    filled_.download(&last, 4, std::size_t(done - 1) * 4);
    if (last == 0) return done;  // a pass that filled nothing: every later one would copy
    seq.begin();
    seq.begin_stage("inpaint");
  }
}

int ForwardWarper::inpaint_until_filled(gpu::Sequence& seq, int max_passes, int batch,
                                        double* gpu_ms) {
  return run_until_filled(seq, inpaint_, buffers_, max_passes, batch, gpu_ms, &result_);
}

void ForwardWarper::record_color_sample(gpu::Sequence& seq, const gpu::Buffer& distance,
                                        const gpu::Buffer& source_color) {
  if (!options_.color) throw std::logic_error("forward warp: colour needs WarpOptions::color");
  if (source_color.size() < pixels(source()) * 4 || distance.size() < pixels(source()) * 4)
    throw std::invalid_argument("forward warp: a source buffer holds fewer than its pixels");
  const float tolerance = float(options_.occlusion_tolerance);
  seq.dispatch(*sample_color_,
               {cameras_, gpu::Texels(result(), gpu::TexelFormat::kR32Uint),
                gpu::Texels(distance, gpu::TexelFormat::kR32Float),
                gpu::Texels(source_color, gpu::TexelFormat::kR32Uint), color_buffers_[0]},
               tolerance, sample_color_->groups_for(target().width, target().height));
  seq.barrier();
  color_result_ = 0;
}

void ForwardWarper::record_color(gpu::Sequence& seq, const gpu::Buffer& distance,
                                 const gpu::Buffer& source_color) {
  record_color_sample(seq, distance, source_color);
  record_inpaint(seq, *inpaint_color_, color_buffers_.data(), 0, options_.inpaint_passes,
                 &color_result_);
}

int ForwardWarper::inpaint_color_until_filled(gpu::Sequence& seq, int max_passes, int batch,
                                              double* gpu_ms) {
  if (!options_.color) throw std::logic_error("forward warp: colour needs WarpOptions::color");
  return run_until_filled(seq, *inpaint_color_, color_buffers_.data(), max_passes, batch, gpu_ms,
                          &color_result_);
}

const gpu::Buffer& ForwardWarper::result() const { return buffers_[result_]; }

const gpu::Buffer& ForwardWarper::color_result() const {
  if (!options_.color) throw std::logic_error("forward warp: no colour without WarpOptions::color");
  return color_buffers_[color_result_];
}

FloatImage ForwardWarper::download(int layer) const {
  if (layer < 0 || layer >= int(layers_.size()))
    throw std::out_of_range("forward warp: no layer " + std::to_string(layer));
  FloatImage out(int(target().width), int(target().height));
  std::vector<std::uint32_t> bits(out.size());
  result().download(bits.data(), bits.size() * 4, std::size_t(layer) * bits.size() * 4);
  for (std::size_t i = 0; i < out.size(); ++i) {
    if (bits[i] != kEmpty) std::memcpy(&out.data()[i], &bits[i], 4);
  }
  return out;
}

Rgb8Image ForwardWarper::download_color() const {
  if (!options_.color)
    throw std::logic_error("forward warp: download_color needs WarpOptions::color");
  const std::vector<std::uint32_t> packed = color_result().download<std::uint32_t>();
  Rgb8Image out(int(target().width), int(target().height));
  std::uint8_t* rgb = out.data();
  for (std::size_t p = 0; p < packed.size(); ++p) {
    for (int c = 0; c < 3; ++c) rgb[3 * p + c] = std::uint8_t(packed[p] >> (8 * c));
  }
  return out;
}

}  // namespace omnisweep::reproject
