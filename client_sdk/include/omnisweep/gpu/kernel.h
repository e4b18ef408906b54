// One compute kernel: a pipeline built from embedded SPIR-V (shaders/<name>.comp), with buffer
// bindings (storage, texel or uniform buffers; each binding may be an array), then storage image
// bindings, push constants and specialization constants. Workgroup sizes are specialization
// constants 100, 101, 102 (local_size_x_id etc. in the shader), so the host always knows them.
#pragma once

#include <array>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "omnisweep/gpu/context.h"
#include "omnisweep/gpu/shaders.h"
#include "omnisweep/gpu/vulkan.h"

namespace omnisweep::gpu {

struct SpecConstant {
  std::uint32_t id = 0;
  std::uint32_t bits = 0;  // the value's 32 bits (int, uint, or float via of())

  static SpecConstant of(std::uint32_t id, std::uint32_t value) { return {id, value}; }
  static SpecConstant of(std::uint32_t id, std::int32_t value) {
    return {id, std::uint32_t(value)};
  }
  static SpecConstant of(std::uint32_t id, float value) {
    std::uint32_t bits;
    std::memcpy(&bits, &value, 4);
    return {id, bits};
  }
};

// What a buffer binding holds: storage buffers (read and written), uniform texel buffers (read
// with texelFetch: a vector gather on CPU devices, the texture cache on GPUs; Buffer::texel_view)
// or uniform buffers (small read-only records every invocation reads, such as cameras: one
// scalar load on CPU devices, the constant cache on GPUs).
enum class BindingKind { kStorageBuffer, kTexelBuffer, kUniformBuffer };

// One binding of buffers: its kind and how many (1 for a plain buffer, N for an array).
struct BindingSlot {
  BindingKind kind = BindingKind::kStorageBuffer;
  std::uint32_t count = 1;
  BindingSlot(std::uint32_t storage_buffers) : count(storage_buffers) {}  // NOLINT: {1, 1, 8}
  BindingSlot(BindingKind k, std::uint32_t n = 1) : kind(k), count(n) {}
  static BindingSlot texels(std::uint32_t n = 1) { return {BindingKind::kTexelBuffer, n}; }
  static BindingSlot uniform() { return {BindingKind::kUniformBuffer, 1}; }
};

struct KernelLayout {
  // The buffer bindings in binding order; a plain number is that many storage buffers.
  std::vector<BindingSlot> bindings{};
  // Storage images, one per binding, at the binding numbers after the buffers.
  std::uint32_t storage_images = 0;
  std::uint32_t push_constant_bytes = 0;
  std::array<std::uint32_t, 3> local_size = {8, 8, 1};
  std::vector<SpecConstant> constants{};

  // `buffers` storage buffers, push constants of `push_bytes`, workgroups of `local`.
  static KernelLayout storage_buffers(std::uint32_t buffers, std::uint32_t push_bytes,
                                      std::array<std::uint32_t, 3> local) {
    KernelLayout l;
    l.bindings.assign(buffers, BindingSlot(1));
    l.push_constant_bytes = push_bytes;
    l.local_size = local;
    return l;
  }
};

// The Vulkan descriptor type of a binding kind.
vk::DescriptorType descriptor_type(BindingKind kind);

class Kernel {
 public:
  // Throws GpuError naming the shader when the pipeline cannot be built, std::invalid_argument
  // when that build of the kernel is not made.
  Kernel(const Context& context, ShaderBuild shader, KernelLayout layout);

  const std::string& name() const { return name_; }
  const KernelLayout& layout() const { return layout_; }
  vk::Pipeline pipeline() const { return *pipeline_; }
  vk::PipelineLayout pipeline_layout() const { return *pipeline_layout_; }
  vk::DescriptorSetLayout set_layout() const { return *set_layout_; }

  // Workgroups needed to cover width x height x depth invocations.
  std::array<std::uint32_t, 3> groups_for(std::uint32_t width, std::uint32_t height,
                                          std::uint32_t depth = 1) const;

 private:
  std::string name_;
  KernelLayout layout_;
  vk::raii::DescriptorSetLayout set_layout_{nullptr};
  vk::raii::PipelineLayout pipeline_layout_{nullptr};
  vk::raii::ShaderModule module_{nullptr};
  vk::raii::Pipeline pipeline_{nullptr};
};

}  // namespace omnisweep::gpu
