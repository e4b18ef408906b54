// The Vulkan runtime on whatever device the machine has (lavapipe here), with the Khronos
// validation layer on: every test fails on any validation message.
#include <gtest/gtest.h>

#include <cstdlib>

#include "omnisweep/gpu/buffer.h"
#include "omnisweep/gpu/command_log.h"
#include "omnisweep/gpu/context.h"
#include "omnisweep/gpu/image.h"
#include "omnisweep/gpu/kernel.h"
#include "omnisweep/gpu/sequence.h"
#include "staging.h"
#include "tests/support/gpu_test_support.h"

namespace omnisweep::gpu {
namespace {

using testing::ValidatedGpuTest;

struct FillPush {
  std::uint32_t count;
  float value;
};

KernelLayout fill_layout(std::uint32_t stride, std::uint32_t local_size) {
  return {.bindings = {1},
          .push_constant_bytes = sizeof(FillPush),
          .local_size = {local_size, 1, 1},
          .constants = {SpecConstant::of(0, stride)}};
}

TEST(Shaders, EveryKernelIsEmbeddedUnderItsFileName) {
  for (int i = 0; i < kShaderCount; ++i) {
    const auto code = embedded_shader(Shader(i));
    ASSERT_GT(code.size(), 5u) << kShaderNames[i];
    EXPECT_EQ(code[0], 0x07230203u) << kShaderNames[i];  // the SPIR-V magic number
    EXPECT_EQ(shader_name(Shader(i)), kShaderNames[i]);
  }
  EXPECT_EQ(shader_name({Shader::kSphereSweepCost, true, true}), "sphere_sweep_cost_f16_x4");
  EXPECT_NE(embedded_shader({Shader::kSphereSweepCost, true, true}).data(),
            embedded_shader({Shader::kSphereSweepCost, false, true}).data());
  EXPECT_FALSE(embedded_shader({Shader::kWinnerTakeAll, false, true}).empty());
  EXPECT_THROW(embedded_shader({Shader::kWinnerTakeAll, true, false}), std::invalid_argument);
}

TEST(GpuDevices, ListsDevicesAndSelectsByIndexOrName) {
  const auto devices = list_devices();
  ASSERT_FALSE(devices.empty());
  for (const auto& d : devices) std::cout << d.index << ": " << d.name << " (" << d.type << ")\n";
  const Context by_index(ContextOptions{.device = "0", .validation = false, .hidden_memory = {}});
  EXPECT_EQ(by_index.info().name, devices[0].name);
  const std::string fragment = devices[0].name.substr(0, 4);
  const Context by_name(
      ContextOptions{.device = fragment, .validation = false, .hidden_memory = {}});
  EXPECT_NE(by_name.info().name.find(fragment), std::string::npos);
  try {
    Context none(ContextOptions{.device = "no-such-gpu", .validation = false, .hidden_memory = {}});
    FAIL();
  } catch (const GpuError& e) {
    EXPECT_NE(std::string(e.what()).find("no Vulkan device matches 'no-such-gpu'"),
              std::string::npos);
    EXPECT_NE(std::string(e.what()).find(devices[0].name), std::string::npos)
        << "lists the devices";
  }
}

TEST(GpuDevices, NoDeviceIsAClearError) {
  // Point the loader at no driver at all.
  const char* saved = std::getenv("VK_ICD_FILENAMES");
  const std::string saved_value = saved ? saved : "";
  ::setenv("VK_ICD_FILENAMES", "/nonexistent/omnisweep_icd.json", 1);
  ::setenv("VK_DRIVER_FILES", "/nonexistent/omnisweep_icd.json", 1);
  try {
    Context context(ContextOptions{});
    ADD_FAILURE() << "a context was created without a driver";
  } catch (const GpuError& e) {
    const std::string what = e.what();
    EXPECT_TRUE(what.find("no Vulkan device") != std::string::npos ||
                what.find("cannot create a Vulkan instance") != std::string::npos)
        << what;
  }
  ::unsetenv("VK_DRIVER_FILES");
  if (saved)
    ::setenv("VK_ICD_FILENAMES", saved_value.c_str(), 1);
  else
    ::unsetenv("VK_ICD_FILENAMES");
}

TEST_F(ValidatedGpuTest, ReportsLimitsOfTheDevice) {
  const DeviceInfo& info = context().info();
  std::cout << info.name << ": maxStorageBufferRange " << (info.max_storage_buffer_range >> 20)
            << " MiB, " << info.max_workgroup_invocations << " invocations per workgroup, "
            << info.max_storage_buffers_per_stage << " storage buffers per stage, timestamps "
            << (info.timestamps ? "yes" : "no") << "\n";
  EXPECT_GE(info.max_storage_buffer_range, 128u << 20);
  EXPECT_GE(info.max_workgroup_invocations, 128u);
}

TEST_F(ValidatedGpuTest, BufferRoundTripAndBounds) {
  Buffer buffer(context(), 1000 * sizeof(float));
  std::vector<float> values(1000);
  for (int i = 0; i < 1000; ++i) values[i] = 0.5f * float(i);
  buffer.upload(std::span<const float>(values));
  EXPECT_EQ(buffer.download<float>(), values);
  EXPECT_EQ(context().allocated_bytes(), 4000u);
  std::vector<float> part(10);
  buffer.download(part.data(), 40, 400);
  EXPECT_EQ(part[0], 50.0f);
  EXPECT_THROW(buffer.download(part.data(), 40, 3980), GpuError);
  EXPECT_THROW(Buffer(context(), 0), GpuError);
  Buffer moved = std::move(buffer);
  EXPECT_EQ(moved.download<float>()[999], 499.5f);
}

TEST(GpuMemory, HiddenMemoryListsParseAndBadItemsAreNamed) {
  EXPECT_EQ(HiddenMemory::parse("").describe(), "none");
  EXPECT_EQ(HiddenMemory::parse("none").describe(), "none");
  EXPECT_EQ(HiddenMemory::parse("cached, device-host").describe(), "device-host,cached");
  EXPECT_EQ(HiddenMemory::parse("all").describe(), "device-host,cached,coherent");
  try {
    HiddenMemory::parse("cached,uncached");
    FAIL();
  } catch (const GpuError& e) {
    EXPECT_NE(std::string(e.what()).find("'uncached'"), std::string::npos) << e.what();
  }
}

// Every memory path a real GPU may take, on whatever device this is: with each property hidden
// (a discrete GPU without resizable BAR, no cached or no coherent host memory), buffers and
// images still round-trip through a kernel, staging is reused, and the layer stays silent.
class GpuMemoryPaths : public ::testing::TestWithParam<const char*> {};

TEST_P(GpuMemoryPaths, TransfersAndKernelsWorkOnEveryFallback) {
  const HiddenMemory hidden = HiddenMemory::parse(GetParam());
  Context context(ContextOptions{.device = ContextOptions::from_environment().device,
                                 .validation = true,
                                 .hidden_memory = hidden});
  Buffer buffer(context, 4096 * sizeof(float));
  EXPECT_TRUE(!hidden.device_host || !buffer.memory().mapped);
  EXPECT_TRUE(!hidden.host_cached || !buffer.memory().cached);
  EXPECT_TRUE(!hidden.host_coherent || !buffer.memory().coherent);
  std::vector<float> values(4096);
  for (int i = 0; i < 4096; ++i) values[i] = 0.25f * float(i);
  buffer.upload(std::span<const float>(values));
  EXPECT_EQ(buffer.download<float>(), values);
  std::vector<float> part(16);
  buffer.download(part.data(), 64, 400);
  EXPECT_EQ(part[0], 25.0f);

  // A kernel overwrites part of it; the download sees the device's writes.
  const Kernel fill(context, Shader::kFill, fill_layout(1, 64));
  Sequence seq(context);
  seq.begin();
  seq.dispatch(fill, {buffer}, FillPush{100, 3.0f}, fill.groups_for(100, 1));
  seq.submit_and_wait();
  const auto out = buffer.download<float>();
  EXPECT_EQ(out[99], 3.0f);
  EXPECT_EQ(out[100], 25.0f);

  std::vector<std::uint32_t> texels(std::size_t(37) * 11), back(texels.size());
  for (std::size_t i = 0; i < texels.size(); ++i) texels[i] = std::uint32_t(i * 2654435761u);
  Image image(context, 37, 11, ImageFormat::kRgba8);
  image.upload(texels.data(), texels.size() * 4);
  image.download(back.data(), back.size() * 4);
  EXPECT_EQ(back, texels);

  // Staging grew once to fit and is reused: the same transfers again allocate nothing more.
  const std::size_t staging = context.staging().bytes();
  for (int i = 0; i < 3; ++i) {
    buffer.upload(std::span<const float>(values));
    image.download(back.data(), back.size() * 4);
  }
  EXPECT_EQ(context.staging().bytes(), staging);
  EXPECT_EQ(context.take_validation_messages(), std::vector<std::string>{});
}

INSTANTIATE_TEST_SUITE_P(Hidden, GpuMemoryPaths,
                         ::testing::Values("none", "device-host", "cached", "coherent",
                                           "device-host,cached", "all"),
                         [](const auto& info) {
                           std::string name = info.param;
                           for (char& c : name)
                             if (c == '-' || c == ',') c = '_';
                           return name;
                         });

TEST_F(ValidatedGpuTest, KernelWithPushAndSpecializationConstants) {
  Buffer buffer(context(), 100 * sizeof(float));
  std::vector<float> zeros(100, -1.0f);
  buffer.upload(std::span<const float>(zeros));
  const Kernel every(context(), Shader::kFill, fill_layout(1, 64));
  const Kernel every_third(context(), Shader::kFill, fill_layout(3, 32));
  Sequence seq(context());
  seq.begin();
  seq.begin_stage("fill");
  seq.dispatch(every, {buffer}, FillPush{50, 2.5f}, every.groups_for(50, 1));
  seq.barrier();
  seq.dispatch(every_third, {buffer}, FillPush{100, 7.0f}, every_third.groups_for(34, 1));
  seq.end_stage();
  seq.submit_and_wait();
  const auto out = buffer.download<float>();
  for (int i = 0; i < 100; ++i) {
    const float expected = i % 3 == 0 ? 7.0f : (i < 50 ? 2.5f : -1.0f);
    ASSERT_EQ(out[i], expected) << i;
  }
  if (context().info().timestamps) {
    ASSERT_EQ(seq.stage_ms().size(), 1u);
    EXPECT_EQ(seq.stage_ms()[0].first, "fill");
    EXPECT_GE(seq.stage_ms()[0].second, 0.0);
  }
}

// The command log counts what was recorded: dispatches with the bytes of what they bind,
// barriers, waits and transfers, by stage; against counts made here from the sizes.
TEST_F(ValidatedGpuTest, CommandLogCountsTheRecordedStream) {
  CommandLog log;
  context().set_command_log(&log);
  Buffer a(context(), vk::DeviceSize(1000) * 4);
  Image image(context(), 13, 7, ImageFormat::kRgba8);
  std::vector<float> values(1000, 1.0f);
  a.upload(std::span<const float>(values));  // a transfer (a round trip where it is staged)
  const Kernel fill(context(), Shader::kFill, fill_layout(1, 64));
  const Kernel copy(
      context(), Shader::kCopyImageToBuffer,
      {.bindings = {1}, .storage_images = 1, .push_constant_bytes = 12, .constants = {}});
  Sequence seq(context());
  seq.begin();
  seq.begin_stage("one");
  seq.dispatch(fill, {a}, FillPush{1000, 2.0f}, fill.groups_for(1000, 1));
  seq.barrier();
  seq.begin_stage("two");
  struct {
    std::uint32_t width, height;
    float gain;
  } push{13, 7, 1.0f};
  seq.dispatch(copy, {a, image}, push, copy.groups_for(13, 7));
  seq.barrier();
  seq.dispatch(fill, {a}, FillPush{10, 1.0f}, fill.groups_for(10, 1));
  seq.submit_and_wait();
  (void)a.download<float>();
  context().set_command_log(nullptr);

  EXPECT_EQ(log.stages(), (std::vector<std::string>{CommandLog::kTransferStage, "one", "two"}));
  const CommandTotals one = log.totals("one"), two = log.totals("two"), all = log.totals();
  EXPECT_EQ(one.dispatches, 1u);
  EXPECT_EQ(one.bound_bytes, 4000u);
  EXPECT_EQ(one.invocations, 16u * 64u);  // 16 groups of 64
  EXPECT_EQ(one.barriers, 1u);
  EXPECT_EQ(one.round_trips, 0u);
  EXPECT_EQ(two.dispatches, 2u);
  EXPECT_EQ(two.bound_bytes, 4000u + 13u * 7u * 4u + 4000u);
  EXPECT_EQ(two.barriers, 1u);
  EXPECT_EQ(two.round_trips, 1u);  // the submit, charged to its last stage
  EXPECT_EQ(all.dispatches, 3u);
  EXPECT_EQ(all.upload_bytes, 4000u);
  EXPECT_EQ(all.download_bytes, 4000u);
  // The image's move into its resting layout and staged transfers wait for the GPU; mapped
  // transfers do not.
  const std::uint64_t staged = a.memory().mapped ? 0 : 1;
  const std::uint64_t staged_down = (a.memory().mapped && a.memory().cached) ? 0 : 1;
  EXPECT_EQ(log.totals(CommandLog::kTransferStage).round_trips, 1 + staged + staged_down);
  EXPECT_EQ(log.dispatches()[1].kernel, "copy_image_to_buffer");
}

TEST_F(ValidatedGpuTest, StorageImagesRoundTripAndBindInKernels) {
  const int w = 13, h = 7;
  std::vector<std::uint32_t> texels(std::size_t(w) * h);
  for (int i = 0; i < w * h; ++i)
    texels[i] = std::uint32_t(i) | (std::uint32_t(2 * i) << 8) | (40u << 16) | (255u << 24);
  Image image(context(), w, h, ImageFormat::kRgba8);
  image.upload(texels.data(), texels.size() * 4);
  std::vector<std::uint32_t> back(std::size_t(w) * h);
  image.download(back.data(), back.size() * 4);
  EXPECT_EQ(back, texels);
  EXPECT_THROW(image.upload(texels.data(), 12), GpuError);

  // A kernel reads it (imageLoad) and writes a buffer, halving every channel.
  Buffer packed(context(), texels.size() * 4);
  const Kernel copy(context(), Shader::kCopyImageToBuffer,
                    {.bindings = {1}, .storage_images = 1, .push_constant_bytes = 12});
  Sequence seq(context());
  seq.begin();
  struct {
    std::uint32_t width, height;
    float gain;
  } push{std::uint32_t(w), std::uint32_t(h), 0.5f};
  seq.dispatch(copy, {packed, image}, push, copy.groups_for(w, h));
  EXPECT_THROW(seq.dispatch(copy, {packed, packed}, push, copy.groups_for(w, h)), GpuError);
  seq.submit_and_wait();
  const auto out = packed.download<std::uint32_t>();
  for (int i = 0; i < w * h; ++i) {
    for (int c = 0; c < 4; ++c) {
      const int v = int((texels[i] >> (8 * c)) & 255), got = int((out[i] >> (8 * c)) & 255);
      ASSERT_NEAR(got, v / 2.0, 0.51) << "texel " << i << " channel " << c;
    }
  }
  Image moved = std::move(image);
  EXPECT_EQ(moved.width(), w);
  EXPECT_THROW(Image(context(), 0, 5, ImageFormat::kR32f), GpuError);
}

TEST_F(ValidatedGpuTest, MisuseIsAnErrorNotACrash) {
  Buffer buffer(context(), 64);
  const Kernel fill(context(), Shader::kFill, fill_layout(1, 64));
  Sequence seq(context());
  EXPECT_THROW(seq.dispatch(fill, {buffer}, FillPush{1, 1.0f}, {1, 1, 1}),
               GpuError);  // before begin()
  seq.begin();
  EXPECT_THROW(seq.dispatch(fill, {}, FillPush{1, 1.0f}, {1, 1, 1}), GpuError);
  EXPECT_THROW(seq.dispatch(fill, {buffer}, 1.0f, {1, 1, 1}), GpuError);
  EXPECT_THROW(seq.dispatch(fill, {buffer}, FillPush{1, 1.0f}, {0, 1, 1}), GpuError);
  const std::uint64_t too_big = context().info().max_storage_buffer_range + 4096;
  if (too_big < (1ull << 31)) {
    Buffer big(context(), too_big);
    EXPECT_THROW(seq.dispatch(fill, {big}, FillPush{1, 1.0f}, {1, 1, 1}), GpuError);
  }
  // fill has no 16-bit build (only the cost-volume kernels do).
  EXPECT_THROW(Kernel(context(), {Shader::kFill, /*half_values=*/true}, fill_layout(1, 64)),
               std::invalid_argument);
  seq.submit_and_wait();
}

TEST_F(ValidatedGpuTest, ValidationLayerCatchesMisuse) {
  // A size-0 buffer created behind the runtime's back is invalid usage (VUID-...-size-00912);
  // the layer must report it, or the other tests' silence would prove nothing.
  const VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO,
                                nullptr,
                                0,
                                0,
                                VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                VK_SHARING_MODE_EXCLUSIVE,
                                0,
                                nullptr};
  VkBuffer raw = VK_NULL_HANDLE;
  const auto& device = context().device();
  const VkResult result = device.getDispatcher()->vkCreateBuffer(*device, &info, nullptr, &raw);
  if (result == VK_SUCCESS && raw != VK_NULL_HANDLE)
    device.getDispatcher()->vkDestroyBuffer(*device, raw, nullptr);
  const auto messages = context().take_validation_messages();
  ASSERT_FALSE(messages.empty()) << "the validation layer reported nothing";
  EXPECT_NE(messages[0].find("00912"), std::string::npos) << messages[0];
}

}  // namespace
}  // namespace omnisweep::gpu
