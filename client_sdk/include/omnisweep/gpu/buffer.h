// A Vulkan storage buffer with its memory, owned (move-only). Buffers live in device-local memory
// (Context::choose_memory); where that memory is also host-visible on a large heap (CPU devices,
// unified-memory boards such as Jetson, resizable BAR) uploads write it through a mapping, and
// where it is also host-cached downloads read it so; every other transfer goes through the
// context's reused staging buffers.
#pragma once

#include <cstddef>
#include <memory>
#include <mutex>
#include <span>
#include <utility>
#include <vector>

#include "omnisweep/gpu/context.h"
#include "omnisweep/gpu/vulkan.h"

namespace omnisweep::gpu {

// How a kernel reads a buffer through a uniform texel buffer (GLSL usamplerBuffer / samplerBuffer
// with texelFetch). Reads of texel buffers are gathers on CPU devices (lavapipe fetches eight
// lanes with one vector gather, where a storage-buffer load is a loop over the lanes) and go
// through the texture cache on GPUs; the values are the buffer's bits, unfiltered. (buffer.cc
// keeps a table in this order.)
enum class TexelFormat {
  kR32Uint,      // usamplerBuffer, one uint per texel
  kRgba32Uint,   // usamplerBuffer, a uvec4 per texel (16 bytes)
  kR32Float,     // samplerBuffer, one float per texel
  kR16Float,     // samplerBuffer, one 16-bit float per texel (read as float)
  kRgba16Float,  // samplerBuffer, four 16-bit floats per texel (read as vec4)
  kRgba32Float,  // samplerBuffer, a vec4 per texel
};
std::uint32_t texel_bytes(TexelFormat format);

class Buffer {
 public:
  // Throws GpuError for a size of zero or when the device cannot allocate it.
  Buffer(Context& context, vk::DeviceSize bytes);
  ~Buffer();
  Buffer(Buffer&& other) noexcept;
  Buffer& operator=(Buffer&& other) noexcept;
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;

  vk::DeviceSize size() const { return size_; }
  vk::Buffer handle() const { return *buffer_; }
  // The memory it lives in and how it is reached (mapped or through staging).
  const MemoryChoice& memory() const { return memory_; }

  // A view of the whole buffer as texels of `format` (whole texels only), made on first use and
  // kept while the buffer lives. Throws GpuError when the buffer holds more texels than the
  // device's maxTexelBufferElements.
  vk::BufferView texel_view(TexelFormat format) const;

  void upload(const void* data, std::size_t bytes, std::size_t offset = 0);
  void download(void* data, std::size_t bytes, std::size_t offset = 0) const;

  template <typename T>
  void upload(std::span<const T> values, std::size_t offset = 0) {
    upload(values.data(), values.size_bytes(), offset);
  }
  template <typename T>
  std::vector<T> download() const {
    std::vector<T> out(size_ / sizeof(T));
    download(out.data(), out.size() * sizeof(T));
    return out;
  }

 private:
  void check_range(std::size_t bytes, std::size_t offset) const;

  Context* context_;
  vk::DeviceSize size_;
  MemoryChoice memory_;
  vk::raii::Buffer buffer_{nullptr};
  vk::raii::DeviceMemory device_memory_{nullptr};
  void* mapped_ = nullptr;
  // Texel views by format, made on demand (the mutex: recording threads may share a buffer).
  mutable std::unique_ptr<std::mutex> views_mutex_ = std::make_unique<std::mutex>();
  mutable std::vector<std::pair<TexelFormat, vk::raii::BufferView>> views_;
};

}  // namespace omnisweep::gpu
