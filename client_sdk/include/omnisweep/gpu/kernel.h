// One compute kernel: a pipeline built from embedded SPIR-V (shaders/<name>.comp), with storage
// buffer bindings (each binding may be an array of buffers), then storage image bindings, then
// uniform texel buffer bindings, push constants and specialization constants. Workgroup sizes are specialization constants 100, 101,
// 102 (local_size_x_id etc. in the shader), so the host always knows them.
#pragma once

#include <array>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "omnisweep/gpu/context.h"

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

struct KernelLayout {
  // Number of storage buffers at each binding (1 for a plain buffer, N for an array).
  std::vector<std::uint32_t> bindings;
  // Storage images, one per binding, at the binding numbers after the buffers.
  std::uint32_t storage_images = 0;
  // Uniform texel buffers (read with texelFetch), one per binding, after the storage images.
  std::uint32_t texel_buffers = 0;
  std::uint32_t push_constant_bytes = 0;
  std::array<std::uint32_t, 3> local_size = {8, 8, 1};
  std::vector<SpecConstant> constants;
};

class Kernel {
 public:
  // Throws GpuError naming the shader when it is unknown or the pipeline cannot be built.
  Kernel(const Context& context, const std::string& shader, KernelLayout layout);

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
