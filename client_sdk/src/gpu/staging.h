// The staging buffers behind every host transfer of a Context: one for uploads (host-visible,
// coherent where there is such memory), one for readback (host-visible and cached where there is
// such memory, so the host reads RAM, not uncached device memory through a mapping). Each grows
// to the largest transfer seen and is then reused, so a frame's transfers allocate nothing.
#pragma once

#include <cstddef>
#include <mutex>

#include "omnisweep/gpu/context.h"
#include "omnisweep/gpu/vulkan.h"

namespace omnisweep::gpu {

// Makes host writes to mapped `memory` visible to the device (flush) and device writes visible to
// the host (invalidate); nothing to do where the memory is coherent.
void flush_mapped(const Context& context, vk::DeviceMemory memory, bool coherent);
void invalidate_mapped(const Context& context, vk::DeviceMemory memory, bool coherent);

class StagingPool {
 public:
  explicit StagingPool(const Context& context);

  // Exclusive use of one staging buffer of at least `bytes` until the lease is dropped; hold it
  // across the copy that reads or fills it (run_commands waits for the GPU).
  class Lease {
   public:
    void* data() const { return mapped_; }
    vk::Buffer buffer() const { return buffer_; }
    // Makes host writes visible to the device (upload) / device writes to the host (readback);
    // no-ops on coherent memory.
    void flush() const { flush_mapped(*context_, memory_, coherent_); }
    void invalidate() const { invalidate_mapped(*context_, memory_, coherent_); }

   private:
    friend class StagingPool;
    Lease(std::unique_lock<std::mutex> lock, const Context& context, vk::Buffer buffer,
          vk::DeviceMemory memory, void* mapped, bool coherent)
        : lock_(std::move(lock)),
          context_(&context),
          buffer_(buffer),
          memory_(memory),
          mapped_(mapped),
          coherent_(coherent) {}
    std::unique_lock<std::mutex> lock_;
    const Context* context_;
    vk::Buffer buffer_;
    vk::DeviceMemory memory_;
    void* mapped_;
    bool coherent_;
  };

  Lease upload(std::size_t bytes) { return lease(upload_, MemoryUse::kUpload, bytes); }
  Lease readback(std::size_t bytes) { return lease(readback_, MemoryUse::kReadback, bytes); }

  // Bytes of host-visible memory the two buffers hold now.
  std::size_t bytes() const;

 private:
  struct Slot {
    mutable std::mutex mutex;
    vk::raii::Buffer buffer{nullptr};
    vk::raii::DeviceMemory memory{nullptr};
    void* mapped = nullptr;
    std::size_t size = 0;
    bool coherent = false;
  };
  Lease lease(Slot& slot, MemoryUse use, std::size_t bytes);

  const Context* context_;
  Slot upload_, readback_;
};

}  // namespace omnisweep::gpu
