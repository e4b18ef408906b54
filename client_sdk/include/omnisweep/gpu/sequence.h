// Records kernel dispatches, barriers and copies into one command buffer, submits it and waits,
// and measures named stages with GPU timestamp queries (Kompute's Sequence, with owned handles).
//
//   Sequence seq(context);
//   seq.begin();
//   seq.begin_stage("sweep_cost");
//   seq.dispatch(kernel, {{&images}, {&costs}}, push, kernel.groups_for(w, h));
//   seq.end_stage();
//   seq.submit_and_wait();
//   seq.stage_ms();  // {{"sweep_cost", 12.3}}
#pragma once

#include <array>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "omnisweep/gpu/buffer.h"
#include "omnisweep/gpu/image.h"
#include "omnisweep/gpu/kernel.h"

namespace omnisweep::gpu {

// Buffers read as uniform texel buffers of one format (Buffer::texel_view): one, or an array
// for bindings declared with a count > 1.
struct Texels {
  std::vector<const Buffer*> buffers;
  TexelFormat format;
  Texels(const Buffer& buffer, TexelFormat f) : buffers{&buffer}, format(f) {}
  Texels(std::vector<const Buffer*> list, TexelFormat f) : buffers(std::move(list)), format(f) {}
};

// A binding: one buffer, an array of buffers for bindings declared with a count > 1 (storage or
// uniform buffers, as the kernel declares them), texel buffers, or a storage image.
struct Binding {
  std::vector<const Buffer*> buffers;
  const Image* image = nullptr;
  std::optional<TexelFormat> texel_format;             // set for texel buffers
  Binding(const Buffer* buffer) : buffers{buffer} {}   // NOLINT: implicit for brace lists
  Binding(const Buffer& buffer) : buffers{&buffer} {}  // NOLINT
  Binding(std::vector<const Buffer*> list) : buffers(std::move(list)) {}  // NOLINT
  Binding(const Image& storage_image) : image(&storage_image) {}          // NOLINT
  Binding(Texels texels)                                                  // NOLINT
      : buffers(std::move(texels.buffers)), texel_format(texels.format) {}
};

class Sequence {
 public:
  explicit Sequence(const Context& context, std::uint32_t max_dispatches = 512,
                    std::uint32_t max_stages = 32);

  // Starts recording (again): earlier commands, descriptor sets and timings are dropped.
  void begin();

  // Binds `bindings` in order (binding i gets bindings[i]: the kernel's buffers, then its
  // images), pushes `push` and dispatches.
  // Throws GpuError when a binding does not match the kernel's layout or exceeds the device's
  // maxStorageBufferRange, maxUniformBufferRange or maxTexelBufferElements.
  void dispatch(const Kernel& kernel, const std::vector<Binding>& bindings, const void* push,
                std::size_t push_bytes, std::array<std::uint32_t, 3> groups);
  template <typename Push>
  void dispatch(const Kernel& kernel, const std::vector<Binding>& bindings, const Push& push,
                std::array<std::uint32_t, 3> groups) {
    dispatch(kernel, bindings, &push, sizeof(Push), groups);
  }

  // Makes every earlier shader or transfer write visible to later shaders and transfers.
  void barrier();
  void copy(const Buffer& source, Buffer& destination, vk::DeviceSize bytes,
            vk::DeviceSize source_offset = 0, vk::DeviceSize destination_offset = 0);
  // Fills `buffer` with a repeated 32-bit pattern (0 clears).
  void fill(Buffer& buffer, std::uint32_t pattern);

  // Stages for timing; stages nest nowhere: begin_stage closes an open one.
  void begin_stage(const std::string& name);
  void end_stage();

  void submit_and_wait();

  // GPU milliseconds per stage of the last submission, in recording order (same-named stages
  // are summed). Empty on devices without timestamp support.
  std::vector<std::pair<std::string, double>> stage_ms() const;

 private:
  std::string current_stage() const;  // the open stage's name, "" when none

  const Context* context_;
  bool profile_kernels_;  // OMNISWEEP_PROFILE_KERNELS=1 (sequence.cc)
  std::uint32_t max_stages_;
  vk::raii::DescriptorPool pool_{nullptr};
  vk::raii::CommandPool command_pool_{nullptr};  // its own, so sequences record on any thread
  vk::raii::CommandBuffers commands_{nullptr};
  vk::raii::QueryPool queries_{nullptr};
  vk::raii::Fence fence_{nullptr};
  std::vector<std::string> stage_names_;
  bool stage_open_ = false;
  bool recording_ = false;
  std::vector<std::pair<std::string, double>> timings_;
};

}  // namespace omnisweep::gpu
