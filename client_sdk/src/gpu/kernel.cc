#include "omnisweep/gpu/kernel.h"

#include "omnisweep/gpu/shaders.h"

namespace omnisweep::gpu {

Kernel::Kernel(const Context& context, const std::string& shader, KernelLayout layout)
    : name_(shader), layout_(std::move(layout)) {
  const auto code = embedded_shader(shader);
  const auto& props_limits = context.info();
  const std::uint64_t invocations =
      std::uint64_t(layout_.local_size[0]) * layout_.local_size[1] * layout_.local_size[2];
  if (invocations > props_limits.max_workgroup_invocations) {
    throw GpuError("kernel " + shader + ": workgroup of " + std::to_string(invocations) +
                   " invocations exceeds the device limit " +
                   std::to_string(props_limits.max_workgroup_invocations));
  }
  std::uint32_t descriptors = 0;
  for (std::uint32_t count : layout_.bindings) descriptors += count;
  if (descriptors > props_limits.max_storage_buffers_per_stage) {
    throw GpuError("kernel " + shader + ": binds " + std::to_string(descriptors) +
                   " storage buffers, over the limit of " +
                   std::to_string(props_limits.max_storage_buffers_per_stage) + " on " +
                   props_limits.name);
  }
  if (layout_.texel_buffers > props_limits.max_sampled_images_per_stage) {
    throw GpuError("kernel " + shader + ": binds " + std::to_string(layout_.texel_buffers) +
                   " texel buffers, over the limit of " +
                   std::to_string(props_limits.max_sampled_images_per_stage) + " on " +
                   props_limits.name);
  }
  try {
    std::vector<vk::DescriptorSetLayoutBinding> bindings;
    for (std::uint32_t i = 0; i < layout_.bindings.size(); ++i) {
      bindings.emplace_back(i, vk::DescriptorType::eStorageBuffer, layout_.bindings[i],
                            vk::ShaderStageFlagBits::eCompute);
    }
    for (std::uint32_t i = 0; i < layout_.storage_images; ++i) {
      bindings.emplace_back(std::uint32_t(layout_.bindings.size()) + i,
                            vk::DescriptorType::eStorageImage, 1,
                            vk::ShaderStageFlagBits::eCompute);
    }
    for (std::uint32_t i = 0; i < layout_.texel_buffers; ++i) {
      bindings.emplace_back(
          std::uint32_t(layout_.bindings.size() + layout_.storage_images) + i,
          vk::DescriptorType::eUniformTexelBuffer, 1, vk::ShaderStageFlagBits::eCompute);
    }
    set_layout_ = vk::raii::DescriptorSetLayout(context.device(),
                                                vk::DescriptorSetLayoutCreateInfo({}, bindings));
    const vk::PushConstantRange push(vk::ShaderStageFlagBits::eCompute, 0,
                                     layout_.push_constant_bytes);
    const vk::DescriptorSetLayout set = *set_layout_;
    pipeline_layout_ = vk::raii::PipelineLayout(
        context.device(), vk::PipelineLayoutCreateInfo(
                              {}, set,
                              layout_.push_constant_bytes
                                  ? vk::ArrayProxyNoTemporaries<const vk::PushConstantRange>(push)
                                  : nullptr));
    module_ = vk::raii::ShaderModule(
        context.device(), vk::ShaderModuleCreateInfo({}, code.size_bytes(), code.data()));

    std::vector<SpecConstant> constants = layout_.constants;
    for (std::uint32_t i = 0; i < 3; ++i) constants.push_back({100 + i, layout_.local_size[i]});
    std::vector<vk::SpecializationMapEntry> entries;
    std::vector<std::uint32_t> values;
    for (const SpecConstant& c : constants) {
      entries.emplace_back(c.id, std::uint32_t(values.size() * 4), 4);
      values.push_back(c.bits);
    }
    const vk::SpecializationInfo spec(entries,
                                      vk::ArrayProxyNoTemporaries<const std::uint32_t>(values));
    const vk::PipelineShaderStageCreateInfo stage({}, vk::ShaderStageFlagBits::eCompute, *module_,
                                                  "main", &spec);
    pipeline_ = vk::raii::Pipeline(context.device(), nullptr,
                                   vk::ComputePipelineCreateInfo({}, stage, *pipeline_layout_));
  } catch (const vk::SystemError& e) {
    throw GpuError("kernel " + shader + ": cannot build the compute pipeline: " + e.what());
  }
}

std::array<std::uint32_t, 3> Kernel::groups_for(std::uint32_t width, std::uint32_t height,
                                                std::uint32_t depth) const {
  const auto& l = layout_.local_size;
  return {(width + l[0] - 1) / l[0], (height + l[1] - 1) / l[1], (depth + l[2] - 1) / l[2]};
}

}  // namespace omnisweep::gpu
