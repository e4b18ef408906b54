// The Vulkan compute context: a headless instance (no window system), one device chosen by
// --vk-device / OMNISWEEP_VK_DEVICE (an index or a name substring) or else by type
// (discrete > integrated > virtual > CPU), one compute queue. Every Vulkan handle has exactly
// one owner: the vk::raii objects here and in Buffer, Kernel and Sequence.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

#include "omnisweep/gpu/vulkan.h"

namespace omnisweep::gpu {

// Errors of the GPU runtime: no device, bad selector, limits exceeded, failed Vulkan calls.
class GpuError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct ContextOptions {
  // Index ("1") or case-insensitive name substring ("llvmpipe", "nvidia"); empty: best device.
  std::string device;
  // Enable the Khronos validation layer and collect its messages (take_validation_messages).
  bool validation = false;
  // device from OMNISWEEP_VK_DEVICE, validation from OMNISWEEP_VK_VALIDATION=1.
  static ContextOptions from_environment();
};

struct DeviceInfo {
  int index = 0;
  std::string name;
  std::string type;  // "discrete", "integrated", "virtual", "cpu", "other"
  std::string api_version;
  std::uint64_t max_storage_buffer_range = 0;
  std::uint32_t max_workgroup_invocations = 0;
  std::uint32_t max_workgroup_count[3] = {0, 0, 0};
  std::uint32_t max_shared_memory = 0;
  std::uint64_t device_local_bytes = 0;
  bool timestamps = false;
  // shaderStorageBufferArrayDynamicIndexing: kernels may index buffer arrays with loop counters.
  bool buffer_array_indexing = false;
  std::uint32_t max_storage_buffers_per_stage = 0;
  double timestamp_period_ns = 0;
};

// The Vulkan devices present, in the loader's order; throws GpuError without a loader.
std::vector<DeviceInfo> list_devices();

class Context {
 public:
  explicit Context(const ContextOptions& options = ContextOptions::from_environment());
  ~Context();
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;

  const DeviceInfo& info() const { return info_; }
  const vk::raii::Device& device() const { return device_; }
  const vk::raii::PhysicalDevice& physical_device() const { return physical_device_; }
  const vk::raii::Queue& queue() const { return queue_; }
  std::uint32_t queue_family() const { return queue_family_; }
  bool validation_enabled() const { return validation_; }

  // Validation messages collected since the last call (empty without validation).
  std::vector<std::string> take_validation_messages();

  // A memory type with all `required` properties, preferring one that also has `preferred`.
  std::uint32_t find_memory_type(std::uint32_t type_bits, vk::MemoryPropertyFlags required,
                                 vk::MemoryPropertyFlags preferred = {}) const;
  bool memory_type_has(std::uint32_t type, vk::MemoryPropertyFlags flags) const;

  // Bytes of device memory held by live Buffers (and its peak), for memory reports.
  std::uint64_t allocated_bytes() const { return allocated_; }
  std::uint64_t peak_allocated_bytes() const { return peak_allocated_; }
  void track_allocation(std::int64_t bytes);

  // Records commands into a one-shot command buffer, submits and waits. Thread-safe.
  void run_commands(const std::function<void(const vk::raii::CommandBuffer&)>& record) const;
  // Submits to the one queue; thread-safe (Vulkan wants queue access externally synchronised),
  // so stages on different threads (the server's depth and stitch) can share a context.
  void submit(vk::CommandBuffer commands, vk::Fence fence) const;

 private:
  struct Messages {
    std::mutex mutex;
    std::vector<std::string> list;
  };
  struct Locks {
    std::mutex queue;         // vkQueueSubmit
    std::mutex command_pool;  // run_commands' pool (each Sequence has its own)
  };

  bool validation_ = false;
  std::unique_ptr<Messages> messages_;
  std::unique_ptr<Locks> locks_ = std::make_unique<Locks>();
  vk::raii::Context context_;
  vk::raii::Instance instance_{nullptr};
  vk::raii::DebugUtilsMessengerEXT messenger_{nullptr};
  vk::raii::PhysicalDevice physical_device_{nullptr};
  vk::raii::Device device_{nullptr};
  vk::raii::Queue queue_{nullptr};
  vk::raii::CommandPool command_pool_{nullptr};
  std::uint32_t queue_family_ = 0;
  DeviceInfo info_;
  vk::PhysicalDeviceMemoryProperties memory_properties_;
  std::uint64_t allocated_ = 0;
  std::uint64_t peak_allocated_ = 0;
};

}  // namespace omnisweep::gpu
