#include "omnisweep/gpu/context.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <sstream>

#include "omnisweep/gpu/command_log.h"
#include "omnisweep/gpu/vulkan.h"
#include "staging.h"

namespace omnisweep::gpu {
namespace {

constexpr const char* kValidationLayer = "VK_LAYER_KHRONOS_validation";

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

const char* type_name(vk::PhysicalDeviceType type) {
  switch (type) {
    case vk::PhysicalDeviceType::eDiscreteGpu:
      return "discrete";
    case vk::PhysicalDeviceType::eIntegratedGpu:
      return "integrated";
    case vk::PhysicalDeviceType::eVirtualGpu:
      return "virtual";
    case vk::PhysicalDeviceType::eCpu:
      return "cpu";
    default:
      return "other";
  }
}

int type_rank(vk::PhysicalDeviceType type) {
  switch (type) {
    case vk::PhysicalDeviceType::eDiscreteGpu:
      return 0;
    case vk::PhysicalDeviceType::eIntegratedGpu:
      return 1;
    case vk::PhysicalDeviceType::eVirtualGpu:
      return 2;
    case vk::PhysicalDeviceType::eCpu:
      return 3;
    default:
      return 4;
  }
}

std::int64_t compute_queue_family(const vk::raii::PhysicalDevice& device) {
  const auto families = device.getQueueFamilyProperties();
  for (std::size_t i = 0; i < families.size(); ++i) {
    if (families[i].queueFlags & vk::QueueFlagBits::eCompute) return std::int64_t(i);
  }
  return -1;
}

DeviceInfo describe(const vk::raii::PhysicalDevice& device, int index) {
  const auto props = device.getProperties();
  DeviceInfo info;
  info.index = index;
  info.name = props.deviceName.data();
  info.type = type_name(props.deviceType);
  info.api_version = std::to_string(VK_API_VERSION_MAJOR(props.apiVersion)) + "." +
                     std::to_string(VK_API_VERSION_MINOR(props.apiVersion)) + "." +
                     std::to_string(VK_API_VERSION_PATCH(props.apiVersion));
  info.max_storage_buffer_range = props.limits.maxStorageBufferRange;
  info.max_workgroup_invocations = props.limits.maxComputeWorkGroupInvocations;
  for (int i = 0; i < 3; ++i)
    info.max_workgroup_count[i] = props.limits.maxComputeWorkGroupCount[i];
  info.max_shared_memory = props.limits.maxComputeSharedMemorySize;
  const auto memory = device.getMemoryProperties();
  for (std::uint32_t i = 0; i < memory.memoryHeapCount; ++i) {
    if (memory.memoryHeaps[i].flags & vk::MemoryHeapFlagBits::eDeviceLocal) {
      info.device_local_bytes =
          std::max<std::uint64_t>(info.device_local_bytes, memory.memoryHeaps[i].size);
    }
  }
  const std::int64_t family = compute_queue_family(device);
  info.timestamps = family >= 0 && props.limits.timestampComputeAndGraphics &&
                    device.getQueueFamilyProperties()[family].timestampValidBits > 0;
  info.timestamp_period_ns = props.limits.timestampPeriod;
  info.buffer_array_indexing = device.getFeatures().shaderStorageBufferArrayDynamicIndexing;
  if (props.apiVersion >= VK_API_VERSION_1_1) {
    const auto features =
        device.getFeatures2<vk::PhysicalDeviceFeatures2, vk::PhysicalDevice16BitStorageFeatures>();
    info.storage_16bit =
        features.get<vk::PhysicalDevice16BitStorageFeatures>().storageBuffer16BitAccess;
  }
  info.max_storage_buffers_per_stage = props.limits.maxPerStageDescriptorStorageBuffers;
  info.max_texel_buffer_elements = props.limits.maxTexelBufferElements;
  info.max_sampled_images_per_stage = props.limits.maxPerStageDescriptorSampledImages;
  info.max_uniform_buffers_per_stage = props.limits.maxPerStageDescriptorUniformBuffers;
  info.max_uniform_buffer_range = props.limits.maxUniformBufferRange;
  return info;
}

vk::raii::Instance create_instance(const vk::raii::Context& context, bool validation) {
  const vk::ApplicationInfo app("omnisweep", 1, "omnisweep", 1, VK_API_VERSION_1_1);
  std::vector<const char*> layers, extensions;
  if (validation) {
    const auto available = context.enumerateInstanceLayerProperties();
    const bool found =
        std::any_of(available.begin(), available.end(), [](const vk::LayerProperties& p) {
          return std::string(p.layerName.data()) == kValidationLayer;
        });
    if (!found) {
      throw GpuError(std::string("Vulkan validation was requested but ") + kValidationLayer +
                     " is not installed (Debian package vulkan-validationlayers)");
    }
    layers.push_back(kValidationLayer);
    extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
  }
  try {
    return vk::raii::Instance(context, vk::InstanceCreateInfo({}, &app, layers, extensions));
  } catch (const vk::SystemError& e) {
    throw GpuError(
        std::string("cannot create a Vulkan instance (is a Vulkan driver installed? on Debian: "
                    "mesa-vulkan-drivers, or the GPU vendor's driver): ") +
        e.what());
  }
}

}  // namespace

HiddenMemory HiddenMemory::parse(const std::string& list) {
  HiddenMemory hidden;
  std::stringstream items(list);
  std::string item;
  while (std::getline(items, item, ',')) {
    item.erase(0, item.find_first_not_of(' '));
    item.erase(item.find_last_not_of(' ') + 1);
    if (item == "device-host") {
      hidden.device_host = true;
    } else if (item == "cached") {
      hidden.host_cached = true;
    } else if (item == "coherent") {
      hidden.host_coherent = true;
    } else if (item == "all") {
      hidden = {.device_host = true, .host_cached = true, .host_coherent = true};
    } else if (!item.empty() && item != "none") {
      throw GpuError("hidden memory '" + item + "' in '" + list +
                     "' is not one of device-host, cached, coherent, all, none");
    }
  }
  return hidden;
}

std::string HiddenMemory::describe() const {
  std::string out;
  if (device_host) out += "device-host";
  if (host_cached) out += std::string(out.empty() ? "" : ",") + "cached";
  if (host_coherent) out += std::string(out.empty() ? "" : ",") + "coherent";
  return out.empty() ? "none" : out;
}

ContextOptions ContextOptions::from_environment() {
  ContextOptions options;
  if (const char* device = std::getenv("OMNISWEEP_VK_DEVICE")) options.device = device;
  if (const char* hidden = std::getenv("OMNISWEEP_VK_HIDE_MEMORY")) {
    try {
      options.hidden_memory = HiddenMemory::parse(hidden);
    } catch (const GpuError& e) {
      throw GpuError(std::string("OMNISWEEP_VK_HIDE_MEMORY: ") + e.what());
    }
  }
  if (const char* validation = std::getenv("OMNISWEEP_VK_VALIDATION")) {
    options.validation = std::string(validation) == "1";
  }
  return options;
}

std::vector<DeviceInfo> list_devices() {
  vk::raii::Context context;
  const vk::raii::Instance instance = create_instance(context, false);
  std::vector<DeviceInfo> out;
  int index = 0;
  for (const auto& device : vk::raii::PhysicalDevices(instance))
    out.push_back(describe(device, index++));
  return out;
}

// The Vulkan-Hpp objects of a context, in the order they are made (and destroyed in reverse).
struct Context::Vulkan {
  vk::raii::Context context;
  vk::raii::Instance instance{nullptr};
  vk::raii::DebugUtilsMessengerEXT messenger{nullptr};
  vk::raii::PhysicalDevice physical_device{nullptr};
  vk::raii::Device device{nullptr};
  vk::raii::Queue queue{nullptr};
  vk::raii::CommandPool command_pool{nullptr};
  vk::PhysicalDeviceMemoryProperties memory_properties;
};

Context::Context(const ContextOptions& options)
    : validation_(options.validation),
      messages_(std::make_unique<Messages>()),
      vk_(std::make_unique<Vulkan>()),
      hidden_memory_(options.hidden_memory) {
  vk_->instance = create_instance(vk_->context, validation_);
  if (validation_) {
    using Severity = vk::DebugUtilsMessageSeverityFlagBitsEXT;
    using Type = vk::DebugUtilsMessageTypeFlagBitsEXT;
    const auto callback =
        [](VkDebugUtilsMessageSeverityFlagBitsEXT, VkDebugUtilsMessageTypeFlagsEXT,
           const VkDebugUtilsMessengerCallbackDataEXT* data, void* user) -> VkBool32 {
      auto* messages = static_cast<Messages*>(user);
      // Also printed at once: a message often explains a crash that follows before anyone reads the
      // list.
      std::fprintf(stderr, "Vulkan validation: %s\n",
                   data->pMessage ? data->pMessage : "(no message)");
      const std::lock_guard lock(messages->mutex);
      messages->list.emplace_back(data->pMessage ? data->pMessage : "(no message)");
      return VK_FALSE;
    };
    vk_->messenger = vk::raii::DebugUtilsMessengerEXT(
        vk_->instance,
        vk::DebugUtilsMessengerCreateInfoEXT(
            {}, Severity::eWarning | Severity::eError,
            Type::eGeneral | Type::eValidation | Type::ePerformance, callback, messages_.get()));
  }
  vk::raii::PhysicalDevices devices(vk_->instance);
  if (devices.empty()) {
    throw GpuError(
        "no Vulkan device found (install a Vulkan driver; on Debian mesa-vulkan-drivers gives "
        "lavapipe, a CPU device)");
  }
  std::vector<DeviceInfo> infos;
  for (std::size_t i = 0; i < devices.size(); ++i) infos.push_back(describe(devices[i], int(i)));
  auto available = [&] {
    std::string list;
    for (const auto& d : infos)
      list += "\n  " + std::to_string(d.index) + ": " + d.name + " (" + d.type + ")";
    return list;
  };
  int chosen = -1;
  if (!options.device.empty()) {
    const bool is_index = std::all_of(options.device.begin(), options.device.end(), ::isdigit);
    for (const auto& d : infos) {
      if (is_index ? std::to_string(d.index) == options.device
                   : lower(d.name).find(lower(options.device)) != std::string::npos) {
        chosen = d.index;
        break;
      }
    }
    if (chosen < 0)
      throw GpuError("no Vulkan device matches '" + options.device + "'; available:" + available());
  } else {
    for (const auto& d : infos) {
      if (compute_queue_family(devices[d.index]) < 0) continue;
      if (chosen < 0 || type_rank(devices[d.index].getProperties().deviceType) <
                            type_rank(devices[chosen].getProperties().deviceType)) {
        chosen = d.index;
      }
    }
  }
  const std::int64_t family = chosen >= 0 ? compute_queue_family(devices[chosen]) : -1;
  if (family < 0) throw GpuError("no Vulkan device with a compute queue; available:" + available());
  vk_->physical_device = std::move(devices[chosen]);
  info_ = infos[chosen];
  queue_family_ = std::uint32_t(family);
  vk_->memory_properties = vk_->physical_device.getMemoryProperties();

  const float priority = 1.0f;
  const vk::DeviceQueueCreateInfo queue_info({}, queue_family_, 1, &priority);
  vk::PhysicalDevice16BitStorageFeatures storage_16bit;
  storage_16bit.storageBuffer16BitAccess = info_.storage_16bit;
  vk::PhysicalDeviceFeatures2 features;
  features.features.shaderStorageBufferArrayDynamicIndexing = info_.buffer_array_indexing;
  if (info_.storage_16bit) features.pNext = &storage_16bit;
  vk::DeviceCreateInfo device_info({}, queue_info, {}, {}, nullptr);
  device_info.pNext = &features;
  vk_->device = vk::raii::Device(vk_->physical_device, device_info);
  vk_->queue = vk::raii::Queue(vk_->device, queue_family_, 0);
  vk_->command_pool = vk::raii::CommandPool(
      vk_->device,
      vk::CommandPoolCreateInfo(vk::CommandPoolCreateFlagBits::eResetCommandBuffer, queue_family_));
  staging_ = std::make_unique<StagingPool>(*this);
}

Context::Context(const ExternalVulkan& external, const ContextOptions& options)
    : external_(true),
      messages_(std::make_unique<Messages>()),
      vk_(std::make_unique<Vulkan>()),
      hidden_memory_(options.hidden_memory) {
  if (!external.instance || !external.physical_device || !external.device) {
    throw GpuError(std::string("external Vulkan: the ") +
                   (!external.instance          ? "instance"
                    : !external.physical_device ? "physical device"
                                                : "device") +
                   " handle is null");
  }
  // Wrapped, not created: the destructor releases these without destroying them, and so does
  // this guard if a check below throws (the members would otherwise destroy the app's handles).
  vk_->instance = vk::raii::Instance(vk_->context, external.instance);
  struct ReleaseOnThrow {
    Context* context;
    bool armed = true;
    ~ReleaseOnThrow() {
      if (armed) context->release_external();
    }
  } guard{this};
  vk_->physical_device = vk::raii::PhysicalDevice(vk_->instance, external.physical_device);
  int index = 0;  // the device's place in the loader's order, as list_devices() numbers it
  for (const auto& d : vk_->instance.enumeratePhysicalDevices()) {
    if (*d == vk::PhysicalDevice(external.physical_device)) break;
    ++index;
  }
  info_ = describe(vk_->physical_device, index);
  const std::uint32_t api = vk_->physical_device.getProperties().apiVersion;
  if (VK_API_VERSION_MAJOR(api) == 1 && VK_API_VERSION_MINOR(api) < 1)
    throw GpuError("external Vulkan: " + info_.name + " supports Vulkan " + info_.api_version +
                   "; the SDK's kernels need 1.1");
  const auto families = vk_->physical_device.getQueueFamilyProperties();
  if (external.queue_family >= families.size() ||
      !(families[external.queue_family].queueFlags & vk::QueueFlagBits::eCompute) ||
      external.queue_index >= families[external.queue_family].queueCount) {
    throw GpuError("external Vulkan: queue " + std::to_string(external.queue_index) +
                   " of family " + std::to_string(external.queue_family) + " on " + info_.name +
                   " is not a compute queue the device has");
  }
  // What the app did not enable the kernels do without.
  info_.storage_16bit = info_.storage_16bit && external.storage_buffer_16bit_access;
  info_.buffer_array_indexing =
      info_.buffer_array_indexing && external.storage_buffer_array_dynamic_indexing;
  queue_family_ = external.queue_family;
  vk_->memory_properties = vk_->physical_device.getMemoryProperties();
  vk_->device = vk::raii::Device(vk_->physical_device, external.device);
  vk_->queue = vk::raii::Queue(vk_->device, queue_family_, external.queue_index);
  vk_->command_pool = vk::raii::CommandPool(
      vk_->device,
      vk::CommandPoolCreateInfo(vk::CommandPoolCreateFlagBits::eResetCommandBuffer, queue_family_));
  staging_ = std::make_unique<StagingPool>(*this);
  guard.armed = false;
}

void Context::release_external() noexcept {
  // What the SDK made on the app's device goes first, while the device's dispatcher is alive;
  // then the app's handles are let go without being destroyed.
  staging_.reset();
  vk_->command_pool.clear();
  (void)vk_->device.release();
  (void)vk_->instance.release();
}

Context::~Context() {
  // A lost device (vk::DeviceLostError) has nothing left to wait for, and a destructor must not
  // throw: the members are destroyed either way. An app's device is not waited on (every SDK
  // submission has been waited for already, and the app's own work is not the SDK's business).
  try {
    if (*vk_->device && !external_) vk_->device.waitIdle();
  } catch (...) {
  }
  if (external_) release_external();
}

const vk::raii::Device& Context::device() const { return vk_->device; }
const vk::raii::PhysicalDevice& Context::physical_device() const { return vk_->physical_device; }
const vk::raii::Queue& Context::queue() const { return vk_->queue; }
VkDevice Context::vk_device() const { return *vk_->device; }
VkPhysicalDevice Context::vk_physical_device() const { return *vk_->physical_device; }
VkQueue Context::vk_queue() const { return *vk_->queue; }

std::vector<std::string> Context::take_validation_messages() {
  const std::lock_guard lock(messages_->mutex);
  return std::exchange(messages_->list, {});
}

MemoryChoice Context::choose_memory(std::uint32_t type_bits, MemoryUse use,
                                    VkDeviceSize bytes) const {
  using Flag = vk::MemoryPropertyFlagBits;
  const auto& types = vk_->memory_properties.memoryTypes;
  const auto& heaps = vk_->memory_properties.memoryHeaps;
  // A type's properties as this use sees them, less what is hidden. With device_host hidden a
  // type that is both is seen as device-only by compute memory and as host-only by staging.
  const auto seen = [&](std::uint32_t i) {
    vk::MemoryPropertyFlags flags = types[i].propertyFlags;
    if (hidden_memory_.host_cached) flags &= ~vk::MemoryPropertyFlags(Flag::eHostCached);
    if (hidden_memory_.host_coherent) flags &= ~vk::MemoryPropertyFlags(Flag::eHostCoherent);
    if (hidden_memory_.device_host && (flags & Flag::eDeviceLocal) && (flags & Flag::eHostVisible))
      flags = use == MemoryUse::kDevice ? vk::MemoryPropertyFlags(Flag::eDeviceLocal)
                                        : flags & ~vk::MemoryPropertyFlags(Flag::eDeviceLocal);
    return flags;
  };
  vk::DeviceSize largest_device_heap = 0;
  for (std::uint32_t h = 0; h < vk_->memory_properties.memoryHeapCount; ++h)
    if (heaps[h].flags & vk::MemoryHeapFlagBits::eDeviceLocal)
      largest_device_heap = std::max(largest_device_heap, heaps[h].size);
  // Rank of type i for this use, lower is better; -1 where it does not qualify.
  const auto rank = [&](std::uint32_t i) -> int {
    const auto flags = seen(i);
    const bool device = bool(flags & Flag::eDeviceLocal), host = bool(flags & Flag::eHostVisible);
    const bool cached = bool(flags & Flag::eHostCached);
    const bool coherent = bool(flags & Flag::eHostCoherent);
    switch (use) {
      case MemoryUse::kDevice: {
        if (!device) return -1;
        // Mappable device memory saves a copy only where its heap is the device's memory (unified
        // memory, resizable BAR); a 256 MiB BAR window is left to what must live there.
        const vk::DeviceSize heap = heaps[types[i].heapIndex].size;
        const bool large = heap >= largest_device_heap / 2 && heap >= bytes;
        return host ? (large ? 0 : 2) : 1;
      }
      case MemoryUse::kUpload:
        if (!host) return -1;
        return coherent ? 0 : 1;
      case MemoryUse::kReadback:
        if (!host) return -1;
        return cached ? (coherent ? 0 : 1) : (coherent ? 2 : 3);
    }
    return -1;
  };
  std::int64_t best = -1;
  int best_rank = 0;
  for (std::uint32_t i = 0; i < vk_->memory_properties.memoryTypeCount; ++i) {
    if (!(type_bits & (1u << i))) continue;
    const int r = rank(i);
    if (r >= 0 && (best < 0 || r < best_rank)) {
      best = i;
      best_rank = r;
    }
  }
  static const char* const kUseNames[] = {"compute", "upload staging", "readback staging"};
  if (best < 0) {
    throw GpuError(std::string("no Vulkan memory type on ") + info_.name + " serves " +
                   kUseNames[int(use)] + " memory (hidden: " + hidden_memory_.describe() + ")");
  }
  const auto flags = seen(std::uint32_t(best));
  return {.type = std::uint32_t(best),
          .mapped = bool(flags & Flag::eHostVisible),
          .coherent = bool(flags & Flag::eHostCoherent),
          .cached = bool(flags & Flag::eHostCached)};
}

void Context::track_allocation(std::int64_t bytes) {
  const std::uint64_t now = allocated_.fetch_add(std::uint64_t(bytes)) + std::uint64_t(bytes);
  std::uint64_t peak = peak_allocated_.load();
  while (now > peak && !peak_allocated_.compare_exchange_weak(peak, now)) {
  }
}

void Context::run_commands(
    const std::function<void(const vk::raii::CommandBuffer&)>& record) const {
  const std::lock_guard lock(locks_->command_pool);
  vk::raii::CommandBuffers buffers(
      vk_->device,
      vk::CommandBufferAllocateInfo(*vk_->command_pool, vk::CommandBufferLevel::ePrimary, 1));
  const vk::raii::CommandBuffer& cmd = buffers[0];
  cmd.begin(vk::CommandBufferBeginInfo(vk::CommandBufferUsageFlagBits::eOneTimeSubmit));
  record(cmd);
  cmd.end();
  const vk::raii::Fence fence(vk_->device, vk::FenceCreateInfo());
  const vk::CommandBuffer raw = *cmd;
  if (CommandLog* log = command_log()) log->add_round_trip(CommandLog::kTransferStage);
  submit(raw, *fence);
  if (vk_->device.waitForFences(*fence, VK_TRUE, UINT64_MAX) != vk::Result::eSuccess) {
    throw GpuError("waiting for the GPU failed");
  }
}

void Context::submit(VkCommandBuffer commands, VkFence fence) const {
  const std::lock_guard lock(locks_->queue);
  const vk::CommandBuffer command(commands);
  vk_->queue.submit(vk::SubmitInfo({}, {}, command), vk::Fence(fence));
}

}  // namespace omnisweep::gpu
