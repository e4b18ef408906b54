// A Vulkan storage buffer with its memory, owned (move-only). Device buffers live in device-local
// memory; where that memory is also host-visible (CPU devices, unified-memory boards such as
// Jetson) they are mapped and copied directly, elsewhere through a staging buffer.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "omnisweep/gpu/context.h"

namespace omnisweep::gpu {

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
  vk::raii::Buffer buffer_{nullptr};
  vk::raii::DeviceMemory memory_{nullptr};
  void* mapped_ = nullptr;
};

}  // namespace omnisweep::gpu
