#include "server/depth/cost_volume.h"

#include <Eigen/Core>
#include <algorithm>
#include <stdexcept>

namespace omnisweep::depth {

gpu::KernelLayout volume_kernel_layout(std::vector<gpu::BindingSlot> bindings,
                                       std::uint32_t push_bytes, VolumeLayout layout) {
  return {.bindings = std::move(bindings),
          .push_constant_bytes = push_bytes,
          .local_size = {8, 8, 1},
          .constants = {gpu::SpecConstant::of(0, std::uint32_t(layout.channels_per_chunk)),
                        gpu::SpecConstant::of(1, std::uint32_t(layout.chunks))}};
}

gpu::ShaderBuild volume_shader(gpu::Shader shader, VolumeLayout layout, bool stores) {
  return {shader, layout.half && stores, layout.pack == 4};
}

VolumeLayout plan_volume(const gpu::Context& context, int width, int height, int channels,
                         bool half, int slots) {
  half = half && context.info().storage_16bit;
  const std::uint64_t value_bytes = half ? 2 : 4;
  const int pack = channels > 1 ? 4 : 1;
  // A chunk is bound as a storage buffer and read as a texel buffer: both limits hold.
  const std::uint64_t limit =
      std::min<std::uint64_t>(context.info().max_storage_buffer_range,
                              context.info().max_texel_buffer_elements * value_bytes * pack);
  const std::uint64_t pixel_bytes = std::uint64_t(width) * height * value_bytes * slots;
  int per_chunk = std::min((channels + pack - 1) / pack * pack, kMaxChannelsPerChunk);
  while (per_chunk > pack && pixel_bytes * per_chunk > limit)
    per_chunk = ((per_chunk + 1) / 2 + pack - 1) / pack * pack;
  const int chunks = (channels + per_chunk - 1) / per_chunk;
  if (pixel_bytes * per_chunk > limit || chunks > kMaxChunks) {
    throw gpu::GpuError(
        std::to_string(channels) + " channels of " + std::to_string(slots) + " reference(s) at " +
        std::to_string(width) + "x" + std::to_string(height) + " do not fit in " +
        std::to_string(kMaxChunks) + " buffers of at most " + std::to_string(limit >> 20) +
        " MiB (maxStorageBufferRange and maxTexelBufferElements of " + context.info().name +
        "); lower the matching resolution or the number of candidates");
  }
  return {per_chunk, chunks, half, slots, pack};
}

namespace {

// Where channel j (of a chunk) of pixel p lies among a slot's values in a chunk: in texel j / pack
// of the pixel (volume.glsl), at component j % pack.
auto element_of(const VolumeLayout& layout, std::size_t pixels) {
  const std::size_t pack = layout.pack;
  return [pack, pixels](std::size_t j, std::size_t p) {
    return (j / pack * pixels + p) * pack + j % pack;
  };
}

}  // namespace

CostVolume::CostVolume(gpu::Context& context, int width, int height, VolumeLayout layout)
    : width_(width), height_(height), layout_(layout) {
  for (int c = 0; c < layout.chunks; ++c) {
    chunks_.emplace_back(context, std::uint64_t(width) * height * layout.channels_per_chunk *
                                      layout.slots * layout.value_bytes());
  }
}

std::uint64_t CostVolume::bytes() const {
  std::uint64_t total = 0;
  for (const auto& c : chunks_) total += c.size();
  return total;
}

std::vector<const gpu::Buffer*> CostVolume::binding(const gpu::Buffer& dummy) const {
  std::vector<const gpu::Buffer*> out(kMaxChunks, &dummy);
  for (std::size_t c = 0; c < chunks_.size(); ++c) out[c] = &chunks_[c];
  return out;
}

gpu::Texels CostVolume::texels(const gpu::Buffer& dummy) const {
  return gpu::Texels(binding(dummy), layout_.texel_format());
}

std::vector<float> CostVolume::download(int channels, int slot) const {
  const std::size_t pixels = std::size_t(width_) * height_;
  const int k = layout_.channels_per_chunk;
  if (slot < 0 || slot >= layout_.slots) throw std::out_of_range("cost volume: no such slot");
  const std::size_t slot_values = pixels * k, offset = slot_values * slot;
  const auto element = element_of(layout_, pixels);
  std::vector<float> out(pixels * channels);
  for (int c = 0; c < layout_.chunks; ++c) {
    std::vector<float> chunk(slot_values);
    if (layout_.half) {
      std::vector<Eigen::half> halves(slot_values);
      chunks_[c].download(halves.data(), slot_values * 2, offset * 2);
      chunk.assign(halves.begin(), halves.end());
    } else {
      chunks_[c].download(chunk.data(), slot_values * 4, offset * 4);
    }
    for (std::size_t p = 0; p < pixels; ++p) {
      for (int j = 0; j < k && c * k + j < channels; ++j)
        out[p * channels + std::size_t(c * k + j)] = chunk[element(j, p)];
    }
  }
  return out;
}

void CostVolume::upload(const std::vector<float>& values, int channels, int slot) {
  const std::size_t pixels = std::size_t(width_) * height_;
  const int k = layout_.channels_per_chunk;
  if (slot < 0 || slot >= layout_.slots) throw std::out_of_range("cost volume: no such slot");
  const std::size_t offset = pixels * k * slot;
  const auto element = element_of(layout_, pixels);
  for (int c = 0; c < layout_.chunks; ++c) {
    std::vector<float> chunk(pixels * k, 0.0f);
    for (std::size_t p = 0; p < pixels; ++p) {
      for (int j = 0; j < k && c * k + j < channels; ++j)
        chunk[element(j, p)] = values[p * channels + std::size_t(c * k + j)];
    }
    if (layout_.half) {
      const std::vector<Eigen::half> halves(chunk.begin(), chunk.end());
      chunks_[c].upload(std::span<const Eigen::half>(halves), offset * 2);
    } else {
      chunks_[c].upload(std::span<const float>(chunk), offset * 4);
    }
  }
}

}  // namespace omnisweep::depth
