// Vulkan interop as a VR app uses it: the test plays the app. It creates its own instance (with
// the validation layer and its own messenger), device and queue with the plain C API, hands them
// to the SDK (gpu::ExternalVulkan), renders a view of a panorama with the SDK's Reprojector, both
// read back to the host and written into buffers the app allocated, and then checks that the SDK
// left the app's device working: nothing destroyed, no validation message.
#include <gtest/gtest.h>
#include <vulkan/vulkan.h>

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "omnisweep/gpu/context.h"
#include "omnisweep/reproject/reprojector.h"

// What an app includes leaves Vulkan-Hpp (and its NDEBUG rule) out of the app.
#ifdef VULKAN_HPP
#error "omnisweep/gpu/context.h or omnisweep/reproject/reprojector.h included Vulkan-Hpp"
#endif

// The app fills Vulkan's C structs with designated initializers and leaves the rest zero, as C
// apps do; GCC's -Wextra would name every field left out.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#endif

namespace omnisweep::reproject {
namespace {

// The app: instance, device, queue and its own validation messages, destroyed by itself.
class App {
 public:
  App() {
    std::uint32_t count = 0;
    vkEnumerateInstanceLayerProperties(&count, nullptr);
    std::vector<VkLayerProperties> layers(count);
    vkEnumerateInstanceLayerProperties(&count, layers.data());
    for (const auto& l : layers)
      validation_ |= std::string(l.layerName) == "VK_LAYER_KHRONOS_validation";
    const char* layer = "VK_LAYER_KHRONOS_validation";
    const char* extension = VK_EXT_DEBUG_UTILS_EXTENSION_NAME;
    VkApplicationInfo app{.sType = VK_STRUCTURE_TYPE_APPLICATION_INFO,
                          .pApplicationName = "vr-app",
                          .apiVersion = VK_API_VERSION_1_1};
    VkInstanceCreateInfo info{.sType = VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO,
                              .pApplicationInfo = &app,
                              .enabledLayerCount = validation_ ? 1u : 0u,
                              .ppEnabledLayerNames = &layer,
                              .enabledExtensionCount = validation_ ? 1u : 0u,
                              .ppEnabledExtensionNames = &extension};
    if (vkCreateInstance(&info, nullptr, &instance) != VK_SUCCESS) return;
    if (validation_) {
      VkDebugUtilsMessengerCreateInfoEXT m{
          .sType = VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT,
          .messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                             VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT,
          .messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                         VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT,
          .pfnUserCallback =
              [](VkDebugUtilsMessageSeverityFlagBitsEXT, VkDebugUtilsMessageTypeFlagsEXT,
                 const VkDebugUtilsMessengerCallbackDataEXT* data, void* user) -> VkBool32 {
            static_cast<std::vector<std::string>*>(user)->emplace_back(data->pMessage);
            return VK_FALSE;
          },
          .pUserData = &messages};
      const auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
          vkGetInstanceProcAddr(instance, "vkCreateDebugUtilsMessengerEXT"));
      create(instance, &m, nullptr, &messenger_);
    }
    count = 0;
    vkEnumeratePhysicalDevices(instance, &count, nullptr);
    std::vector<VkPhysicalDevice> devices(count);
    vkEnumeratePhysicalDevices(instance, &count, devices.data());
    for (VkPhysicalDevice d : devices) {
      std::uint32_t families = 0;
      vkGetPhysicalDeviceQueueFamilyProperties(d, &families, nullptr);
      std::vector<VkQueueFamilyProperties> props(families);
      vkGetPhysicalDeviceQueueFamilyProperties(d, &families, props.data());
      for (std::uint32_t f = 0; f < families && !physical_device; ++f) {
        if (props[f].queueFlags & VK_QUEUE_COMPUTE_BIT) {
          physical_device = d;
          queue_family = f;
        }
      }
    }
    if (!physical_device) return;
    // The app enables what the SDK can use, where the device has it, and says so.
    VkPhysicalDevice16BitStorageFeatures storage16{
        .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_16BIT_STORAGE_FEATURES};
    VkPhysicalDeviceFeatures2 features{.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2,
                                       .pNext = &storage16};
    vkGetPhysicalDeviceFeatures2(physical_device, &features);
    storage_16bit = storage16.storageBuffer16BitAccess;
    dynamic_indexing = features.features.shaderStorageBufferArrayDynamicIndexing;
    VkPhysicalDevice16BitStorageFeatures enable16{
        .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_16BIT_STORAGE_FEATURES,
        .storageBuffer16BitAccess = storage_16bit};
    VkPhysicalDeviceFeatures2 enable{.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2,
                                     .pNext = &enable16};
    enable.features.shaderStorageBufferArrayDynamicIndexing = dynamic_indexing;
    const float priority = 1.0f;
    VkDeviceQueueCreateInfo queue{.sType = VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO,
                                  .queueFamilyIndex = queue_family,
                                  .queueCount = 1,
                                  .pQueuePriorities = &priority};
    VkDeviceCreateInfo device_info{.sType = VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO,
                                   .pNext = &enable,
                                   .queueCreateInfoCount = 1,
                                   .pQueueCreateInfos = &queue};
    if (vkCreateDevice(physical_device, &device_info, nullptr, &device) != VK_SUCCESS)
      device = VK_NULL_HANDLE;
  }

  ~App() {
    if (device) vkDestroyDevice(device, nullptr);
    if (messenger_) {
      const auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
          vkGetInstanceProcAddr(instance, "vkDestroyDebugUtilsMessengerEXT"));
      destroy(instance, messenger_, nullptr);
    }
    if (instance) vkDestroyInstance(instance, nullptr);
  }
  App(const App&) = delete;
  App& operator=(const App&) = delete;

  gpu::ExternalVulkan handles() const {
    return {.instance = instance,
            .physical_device = physical_device,
            .device = device,
            .queue_family = queue_family,
            .queue_index = 0,
            .storage_buffer_16bit_access = storage_16bit,
            .storage_buffer_array_dynamic_indexing = dynamic_indexing};
  }

  // A host-visible buffer of the app's own that transfers can write.
  struct HostBuffer {
    VkBuffer buffer = VK_NULL_HANDLE;
    VkDeviceMemory memory = VK_NULL_HANDLE;
    void* mapped = nullptr;
  };
  HostBuffer host_buffer(VkDeviceSize bytes) const {
    HostBuffer b;
    VkBufferCreateInfo info{.sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO,
                            .size = bytes,
                            .usage = VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                            .sharingMode = VK_SHARING_MODE_EXCLUSIVE};
    EXPECT_EQ(vkCreateBuffer(device, &info, nullptr, &b.buffer), VK_SUCCESS);
    VkMemoryRequirements needs;
    vkGetBufferMemoryRequirements(device, b.buffer, &needs);
    VkPhysicalDeviceMemoryProperties memory;
    vkGetPhysicalDeviceMemoryProperties(physical_device, &memory);
    const VkMemoryPropertyFlags wanted =
        VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
    std::uint32_t type = 0;
    while (type < memory.memoryTypeCount &&
           !((needs.memoryTypeBits >> type & 1) &&
             (memory.memoryTypes[type].propertyFlags & wanted) == wanted))
      ++type;
    VkMemoryAllocateInfo alloc{.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO,
                               .allocationSize = needs.size,
                               .memoryTypeIndex = type};
    EXPECT_EQ(vkAllocateMemory(device, &alloc, nullptr, &b.memory), VK_SUCCESS);
    vkBindBufferMemory(device, b.buffer, b.memory, 0);
    vkMapMemory(device, b.memory, 0, bytes, 0, &b.mapped);
    return b;
  }
  void destroy(HostBuffer& b) const {
    vkUnmapMemory(device, b.memory);
    vkDestroyBuffer(device, b.buffer, nullptr);
    vkFreeMemory(device, b.memory, nullptr);
  }

  VkInstance instance = VK_NULL_HANDLE;
  VkPhysicalDevice physical_device = VK_NULL_HANDLE;
  VkDevice device = VK_NULL_HANDLE;
  std::uint32_t queue_family = 0;
  bool storage_16bit = false, dynamic_indexing = false;
  std::vector<std::string> messages;

 private:
  bool validation_ = false;
  VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
};

// A 128x64 panorama: a room of 2 m radius with colour bands, and a near box in front.
void panorama(Rgb8Image& color, FloatImage& distance) {
  color = Rgb8Image(128, 64);
  distance = FloatImage::filled(128, 64, 2.0f);
  for (int y = 0; y < 64; ++y) {
    for (int x = 0; x < 128; ++x) {
      color(x, y, 0) = std::uint8_t(2 * x);
      color(x, y, 1) = std::uint8_t(4 * y);
      color(x, y, 2) = std::uint8_t((x / 8 + y / 8) % 2 ? 200 : 40);
      if (x >= 56 && x < 72 && y >= 24 && y < 40) distance(x, y) = 0.8f;
    }
  }
}

TEST(ExternalVulkan, AnAppsOwnDeviceRendersViewsAndIsLeftWorking) {
  App app;
  ASSERT_TRUE(app.instance && app.device) << "the test's own Vulkan device could not be made";
  Rgb8Image color;
  FloatImage distance;
  panorama(color, distance);
  const Rigid3d eye(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0.05, 0, 0));
  const PinholeCamera<double> camera = pinhole_for_fov(96, 80, 90);
  constexpr VkDeviceSize kBytes = VkDeviceSize(96) * 80 * 4;
  App::HostBuffer color_out = app.host_buffer(kBytes), distance_out = app.host_buffer(kBytes);
  View view;
  {
    gpu::Context context(app.handles());
    EXPECT_TRUE(context.external());
    EXPECT_EQ(context.vk_device(), app.device);
    EXPECT_EQ(context.vk_physical_device(), app.physical_device);
    EXPECT_EQ(context.info().storage_16bit, app.storage_16bit);
    Reprojector reprojector(context);
    reprojector.set_panorama(color, distance, Eigen::Vector3d::Zero());
    view = reprojector.render_pinhole(eye, camera, 96, 80);
    const int passes = reprojector.render_pinhole_into(
        eye, camera, 96, 80, {.color = color_out.buffer, .distance = distance_out.buffer});
    EXPECT_EQ(passes, view.inpaint_passes);
  }  // the SDK's context goes; the app's handles must not
  // The app's buffers hold the same view the host read back.
  const auto* rgba = static_cast<const std::uint32_t*>(color_out.mapped);
  const auto* metres = static_cast<const float*>(distance_out.mapped);
  int near = 0;
  for (int i = 0; i < 96 * 80; ++i) {
    for (int c = 0; c < 3; ++c)
      ASSERT_EQ(std::uint8_t(rgba[i] >> (8 * c)), view.color.data()[3 * i + c]) << i;
    const float d = view.distance.data()[i];
    if (d == 0) {
      ASSERT_TRUE(std::isnan(metres[i])) << i;
    } else {
      ASSERT_EQ(metres[i], d) << i;
      near += d < 1.0f;
    }
  }
  EXPECT_GT(near, 100);  // the box is in the view
  // The app's device still works: a buffer made and destroyed, the queue idle.
  app.destroy(color_out);
  app.destroy(distance_out);
  EXPECT_EQ(vkDeviceWaitIdle(app.device), VK_SUCCESS);
  App::HostBuffer after = app.host_buffer(64);
  app.destroy(after);
  EXPECT_TRUE(app.messages.empty()) << app.messages.front();
}

TEST(ExternalVulkan, BadHandlesAreNamed) {
  const auto message = [](const gpu::ExternalVulkan& external) {
    try {
      gpu::Context context(external);
    } catch (const gpu::GpuError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message({}), "external Vulkan: the instance handle is null");
  App app;
  ASSERT_TRUE(app.device);
  gpu::ExternalVulkan bad = app.handles();
  bad.queue_family = 99;
  EXPECT_NE(message(bad).find("queue 0 of family 99"), std::string::npos) << message(bad);
  bad = app.handles();
  bad.device = VK_NULL_HANDLE;
  EXPECT_EQ(message(bad), "external Vulkan: the device handle is null");
  EXPECT_EQ(vkDeviceWaitIdle(app.device), VK_SUCCESS);  // a refused context touched nothing
  EXPECT_TRUE(app.messages.empty()) << app.messages.front();
}

}  // namespace
}  // namespace omnisweep::reproject
