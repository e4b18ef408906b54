#include "server/depth/cost_volume.h"

#include <Eigen/Core>

#include <algorithm>

namespace omnisweep::depth {

gpu::KernelLayout volume_kernel_layout(std::vector<std::uint32_t> bindings,
                                       std::uint32_t push_bytes, VolumeLayout layout) {
  return {.bindings = std::move(bindings),
          .push_constant_bytes = push_bytes,
          .local_size = {8, 8, 1},
          .constants = {gpu::SpecConstant::of(0, std::uint32_t(layout.channels_per_chunk)),
                        gpu::SpecConstant::of(1, std::uint32_t(layout.chunks))}};
}

std::string volume_shader(const std::string& shader, VolumeLayout layout) {
  return layout.half ? shader + "_f16" : shader;
}

VolumeLayout plan_volume(const gpu::Context& context, int width, int height, int channels,
                         bool half) {
  half = half && context.info().storage_16bit;
  const std::uint64_t limit = context.info().max_storage_buffer_range;
  const std::uint64_t pixel_bytes = std::uint64_t(width) * height * (half ? 2 : 4);
  int per_chunk = std::min(channels, kMaxChannelsPerChunk);
  while (per_chunk > 1 && pixel_bytes * per_chunk > limit) per_chunk = (per_chunk + 1) / 2;
  const int chunks = (channels + per_chunk - 1) / per_chunk;
  if (pixel_bytes * per_chunk > limit || chunks > kMaxChunks) {
    throw gpu::GpuError(std::to_string(channels) + " channels at " + std::to_string(width) + "x" +
                        std::to_string(height) + " do not fit in " + std::to_string(kMaxChunks) +
                        " buffers of at most " + std::to_string(limit >> 20) +
                        " MiB (maxStorageBufferRange of " + context.info().name +
                        "); lower the matching resolution or the number of candidates");
  }
  return {per_chunk, chunks, half};
}

CostVolume::CostVolume(gpu::Context& context, int width, int height, VolumeLayout layout)
    : width_(width), height_(height), layout_(layout) {
  for (int c = 0; c < layout.chunks; ++c) {
    chunks_.emplace_back(context, std::uint64_t(width) * height * layout.channels_per_chunk *
                                      layout.value_bytes());
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

std::vector<float> CostVolume::download(int channels) const {
  const std::size_t pixels = std::size_t(width_) * height_;
  const int k = layout_.channels_per_chunk;
  std::vector<float> out(pixels * channels);
  for (int c = 0; c < layout_.chunks; ++c) {
    std::vector<float> chunk;
    if (layout_.half) {
      const std::vector<Eigen::half> halves = chunks_[c].download<Eigen::half>();
      chunk.assign(halves.begin(), halves.end());
    } else {
      chunk = chunks_[c].download<float>();
    }
    for (std::size_t p = 0; p < pixels; ++p) {
      for (int j = 0; j < k && c * k + j < channels; ++j)
        out[p * channels + c * k + j] = chunk[j * pixels + p];
    }
  }
  return out;
}

void CostVolume::upload(const std::vector<float>& values, int channels) {
  const std::size_t pixels = std::size_t(width_) * height_;
  const int k = layout_.channels_per_chunk;
  for (int c = 0; c < layout_.chunks; ++c) {
    std::vector<float> chunk(pixels * k, 0.0f);
    for (std::size_t p = 0; p < pixels; ++p) {
      for (int j = 0; j < k && c * k + j < channels; ++j)
        chunk[j * pixels + p] = values[p * channels + c * k + j];
    }
    if (layout_.half) {
      const std::vector<Eigen::half> halves(chunk.begin(), chunk.end());
      chunks_[c].upload(std::span<const Eigen::half>(halves));
    } else {
      chunks_[c].upload(std::span<const float>(chunk));
    }
  }
}

}  // namespace omnisweep::depth
