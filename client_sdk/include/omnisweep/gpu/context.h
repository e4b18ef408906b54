// The Vulkan compute context: a headless instance (no window system), one device chosen by
// --vk-device / OMNISWEEP_VK_DEVICE (an index or a name substring) or else by type
// (discrete > integrated > virtual > CPU), one compute queue. Every Vulkan handle has exactly
// one owner: the vk::raii objects of the context (held privately) and of Buffer, Kernel and
// Sequence.
//
// This header is what an app includes to make a context (with its own Vulkan or without): it
// needs only the Vulkan C headers, so neither Vulkan-Hpp nor its NDEBUG rule (gpu/vulkan.h)
// reaches the app. The accessors that return Vulkan-Hpp objects are for the SDK's compute runtime
// (gpu/buffer.h, kernel.h, sequence.h, which include Vulkan-Hpp); their types are only declared
// here.
#pragma once

#include <vulkan/vulkan_core.h>

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

// Declared only (see above); gpu/vulkan.h defines them.
namespace vk {
namespace raii {
class CommandBuffer;
class Device;
class PhysicalDevice;
class Queue;
}  // namespace raii
}  // namespace vk

namespace omnisweep::gpu {

// Errors of the GPU runtime: no device, bad selector, limits exceeded, failed Vulkan calls.
class GpuError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Memory properties a context pretends its device lacks, so that a device with one kind of
// memory for everything (lavapipe, Jetson) runs the paths a discrete GPU takes.
struct HiddenMemory {
  // No memory type is both device-local and host-visible (a discrete GPU without resizable BAR):
  // compute buffers are never mapped, every transfer goes through a staging buffer.
  bool device_host = false;
  bool host_cached = false;    // readback falls back to uncached host memory
  bool host_coherent = false;  // mapped memory is flushed and invalidated explicitly
  // Parses a comma-separated list of "device-host", "cached", "coherent" (or "all"; empty: none);
  // throws GpuError naming the bad item.
  static HiddenMemory parse(const std::string& list);
  std::string describe() const;  // the same list back ("none" when nothing is hidden)
};

struct ContextOptions {
  // Index ("1") or case-insensitive name substring ("llvmpipe", "nvidia"); empty: best device.
  std::string device;
  // Enable the Khronos validation layer and collect its messages (take_validation_messages).
  bool validation = false;
  HiddenMemory hidden_memory;
  // device from OMNISWEEP_VK_DEVICE, validation from OMNISWEEP_VK_VALIDATION=1, hidden memory
  // from OMNISWEEP_VK_HIDE_MEMORY (HiddenMemory::parse).
  static ContextOptions from_environment();
};

// What memory serves: compute buffers and images, staging for uploads, staging for readback.
enum class MemoryUse { kDevice, kUpload, kReadback };

// A memory type chosen for a use, with what the code that maps it must do.
struct MemoryChoice {
  std::uint32_t type = 0;
  bool mapped = false;    // host-visible (and not hidden): map it and copy directly
  bool coherent = false;  // no flush / invalidate needed
  bool cached = false;    // host reads are fast (reading uncached device memory is not)
};

class StagingPool;
class CommandLog;

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
  std::uint64_t max_texel_buffer_elements = 0;
  std::uint32_t max_sampled_images_per_stage = 0;  // uniform texel buffers count here
  std::uint32_t max_uniform_buffers_per_stage = 0;
  std::uint64_t max_uniform_buffer_range = 0;
  double timestamp_period_ns = 0;
  // storageBuffer16BitAccess (Vulkan 1.1): kernels may store 16-bit floats in buffers (the *_f16
  // volume kernels); enabled on the device whenever it is present.
  bool storage_16bit = false;
};

// The Vulkan devices present, in the loader's order; throws GpuError without a loader.
std::vector<DeviceInfo> list_devices();

// Vulkan an app already owns (a VR or teleoperation app with its own instance and device): a
// Context made from it runs every SDK kernel on the app's device and queue and never destroys
// the app's handles. The device must support Vulkan 1.1, and its queue family compute. Features
// cannot be read back from a device, so the app says which optional ones it enabled; the SDK
// uses a feature only when it is enabled and supported. The SDK submits to the queue under its
// own lock: the app must not submit to the same queue from another thread while an SDK call
// runs (or hand the SDK a queue index of its own).
struct ExternalVulkan {
  VkInstance instance = VK_NULL_HANDLE;
  VkPhysicalDevice physical_device = VK_NULL_HANDLE;
  VkDevice device = VK_NULL_HANDLE;
  std::uint32_t queue_family = 0;
  std::uint32_t queue_index = 0;
  bool storage_buffer_16bit_access = false;  // VkPhysicalDevice16BitStorageFeatures, enabled
  bool storage_buffer_array_dynamic_indexing = false;  // VkPhysicalDeviceFeatures, enabled
};

class Context {
 public:
  explicit Context(const ContextOptions& options = ContextOptions::from_environment());
  // On the app's own instance, device and queue (ExternalVulkan); `options.device` and
  // `options.validation` do not apply (the app chose its device and layers). Throws GpuError
  // naming what is missing (a null handle, a queue family without compute, Vulkan < 1.1).
  explicit Context(const ExternalVulkan& external, const ContextOptions& options = {});
  ~Context();
  // True for a context made from ExternalVulkan: its instance and device are the app's.
  bool external() const { return external_; }
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;

  const DeviceInfo& info() const { return info_; }
  // The Vulkan-Hpp objects, for the compute runtime (include gpu/vulkan.h to use them).
  const vk::raii::Device& device() const;
  const vk::raii::PhysicalDevice& physical_device() const;
  const vk::raii::Queue& queue() const;
  // The same as Vulkan C handles (the app's own, for an ExternalVulkan context).
  VkDevice vk_device() const;
  VkPhysicalDevice vk_physical_device() const;
  VkQueue vk_queue() const;
  std::uint32_t queue_family() const { return queue_family_; }
  bool validation_enabled() const { return validation_; }

  // Validation messages collected since the last call (empty without validation).
  std::vector<std::string> take_validation_messages();

  // The memory type for `use` among `type_bits`, by a fallback chain (context.cc): compute
  // memory is device-local, and also host-visible only where that heap is large enough for
  // compute buffers (not a 256 MiB BAR); readback prefers cached host memory, upload coherent.
  // Throws GpuError when no type qualifies.
  MemoryChoice choose_memory(std::uint32_t type_bits, MemoryUse use, VkDeviceSize bytes) const;
  const HiddenMemory& hidden_memory() const { return hidden_memory_; }

  // Bytes of device memory held by live Buffers and Images (and its peak), for memory reports.
  // Thread-safe: the server's stages allocate from their own threads.
  std::uint64_t allocated_bytes() const { return allocated_; }
  std::uint64_t peak_allocated_bytes() const { return peak_allocated_; }
  void track_allocation(std::int64_t bytes);

  // Where the runtime records what it is asked to do (null: nowhere, the default). The log must
  // outlive its use; attach it before recording.
  void set_command_log(CommandLog* log) { command_log_ = log; }
  CommandLog* command_log() const { return command_log_; }

  // The staging buffers every transfer reuses (staging.h), one for uploads, one for readback.
  StagingPool& staging() const { return *staging_; }

  // Records commands into a one-shot command buffer, submits and waits. Thread-safe.
  void run_commands(const std::function<void(const vk::raii::CommandBuffer&)>& record) const;
  // Submits to the one queue; thread-safe (Vulkan wants queue access externally synchronised),
  // so stages on different threads (the server's depth and stitch) can share a context.
  void submit(VkCommandBuffer commands, VkFence fence) const;

 private:
  void release_external() noexcept;  // an ExternalVulkan context's: destroys only what it made

  struct Messages {
    std::mutex mutex;
    std::vector<std::string> list;
  };
  struct Locks {
    std::mutex queue;         // vkQueueSubmit
    std::mutex command_pool;  // run_commands' pool (each Sequence has its own)
  };

  struct Vulkan;  // the Vulkan-Hpp objects (context.cc)

  bool validation_ = false;
  bool external_ = false;
  std::unique_ptr<Messages> messages_;
  std::unique_ptr<Locks> locks_ = std::make_unique<Locks>();
  std::unique_ptr<Vulkan> vk_;
  std::uint32_t queue_family_ = 0;
  DeviceInfo info_;
  HiddenMemory hidden_memory_;
  std::atomic<std::uint64_t> allocated_{0};
  std::atomic<std::uint64_t> peak_allocated_{0};
  std::atomic<CommandLog*> command_log_{nullptr};
  std::unique_ptr<StagingPool> staging_;
};

}  // namespace omnisweep::gpu
