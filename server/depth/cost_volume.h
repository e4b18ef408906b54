// A cost volume on the GPU: width x height pixels x `candidates` floats for each of `slots`
// reference cameras (one dispatch covers every slot, z = slot), split into chunks of
// channels_per_chunk candidate planes (of every slot) so that no buffer exceeds the device's
// maxStorageBufferRange or maxTexelBufferElements (see shaders/include/volume.glsl). Also used
// for any multi-channel image the ISB filter takes (the distance maps: one channel).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "omnisweep/gpu/buffer.h"
#include "omnisweep/gpu/kernel.h"
#include "omnisweep/gpu/sequence.h"

namespace omnisweep::depth {

inline constexpr int kMaxChunks =
    8;  // shaders/include/volume.glsl; 2 + 2 x 8 bindings fit the 32 of lavapipe
inline constexpr int kMaxChannelsPerChunk = 32;

struct VolumeLayout {
  int channels_per_chunk = 1;  // a multiple of pack
  int chunks = 1;
  bool half = false;  // values stored as 16-bit floats (the *_f16 kernels)
  int slots = 1;      // reference cameras side by side in every chunk
  int pack = 1;       // channels per texel: 4 (the *_x4 kernels), or 1
  int channels() const { return channels_per_chunk * chunks; }  // candidates plus padding
  std::uint64_t value_bytes() const { return half ? 2 : 4; }
  gpu::TexelFormat texel_format() const {
    if (pack == 4) return half ? gpu::TexelFormat::kRgba16Float : gpu::TexelFormat::kRgba32Float;
    return half ? gpu::TexelFormat::kR16Float : gpu::TexelFormat::kR32Float;
  }
};

// The kernel of `shader` that stores (or, `stores` false, only reads) volumes with `layout`:
// `shader`, or its build for 16-bit values (_f16; a kernel that only reads has none, its texel
// views convert) and for channels packed by four (_x4) (shaders/CMakeLists.txt).
gpu::ShaderBuild volume_shader(gpu::Shader shader, VolumeLayout layout, bool stores = true);

// The layout of a kernel that binds chunk arrays: `bindings` as in gpu::KernelLayout, 8x8x1
// workgroups, and the volume's channels per chunk and chunk count as specialization constants
// 0 and 1 (shaders/include/volume.glsl).
gpu::KernelLayout volume_kernel_layout(std::vector<gpu::BindingSlot> bindings,
                                       std::uint32_t push_bytes, VolumeLayout layout);

// The layout for `channels` channels of `slots` references at width x height on this device,
// 16-bit where `half` and the device stores 16-bit floats, channels packed by four where there
// is more than one (padded to a multiple of four); throws GpuError when even the smallest chunk
// needs more than kMaxChunks chunks.
VolumeLayout plan_volume(const gpu::Context& context, int width, int height, int channels,
                         bool half = false, int slots = 1);

class CostVolume {
 public:
  CostVolume(gpu::Context& context, int width, int height, VolumeLayout layout);

  int width() const { return width_; }
  int height() const { return height_; }
  const VolumeLayout& layout() const { return layout_; }
  std::vector<gpu::Buffer>& chunks() { return chunks_; }
  const std::vector<gpu::Buffer>& chunks() const { return chunks_; }
  std::uint64_t bytes() const;
  // The chunk array as bound by the kernels: unused entries point at `dummy` (at least 16 bytes).
  std::vector<const gpu::Buffer*> binding(const gpu::Buffer& dummy) const;
  // The same array as texel buffers, for reading (volume.glsl).
  gpu::Texels texels(const gpu::Buffer& dummy) const;

  // Host copies of slot `slot` in the layout candidate-major per pixel: out[p * channels + i],
  // i < channels (16-bit volumes are converted, rounding to nearest on upload).
  std::vector<float> download(int channels, int slot = 0) const;
  void upload(const std::vector<float>& values, int channels, int slot = 0);

 private:
  int width_;
  int height_;
  VolumeLayout layout_;
  std::vector<gpu::Buffer> chunks_;
};

}  // namespace omnisweep::depth
