#include "omnisweep/gpu/kernel.h"

#include "omnisweep/gpu/shaders.h"

namespace omnisweep::gpu {

vk::DescriptorType descriptor_type(BindingKind kind) {
  switch (kind) {
    case BindingKind::kTexelBuffer:
      return vk::DescriptorType::eUniformTexelBuffer;
    case BindingKind::kUniformBuffer:
      return vk::DescriptorType::eUniformBuffer;
    case BindingKind::kStorageBuffer:
      break;
  }
  return vk::DescriptorType::eStorageBuffer;
}

Kernel::Kernel(const Context& context, ShaderBuild build, KernelLayout layout)
    : name_(shader_name(build)), layout_(std::move(layout)) {
  const auto code = embedded_shader(build);
  const std::string& shader = name_;
  const auto& props_limits = context.info();
  const std::uint64_t invocations =
      std::uint64_t(layout_.local_size[0]) * layout_.local_size[1] * layout_.local_size[2];
  if (invocations > props_limits.max_workgroup_invocations) {
    throw GpuError("kernel " + shader + ": workgroup of " + std::to_string(invocations) +
                   " invocations exceeds the device limit " +
                   std::to_string(props_limits.max_workgroup_invocations));
  }
  std::uint32_t storage = 0, texels = 0, uniforms = 0;
  for (const BindingSlot& slot : layout_.bindings) {
    (slot.kind == BindingKind::kStorageBuffer ? storage
     : slot.kind == BindingKind::kTexelBuffer ? texels
                                              : uniforms) += slot.count;
  }
  const auto check = [&](std::uint32_t count, std::uint32_t limit, const char* what) {
    if (count > limit) {
      throw GpuError("kernel " + shader + ": binds " + std::to_string(count) + " " + what +
                     ", over the limit of " + std::to_string(limit) + " on " + props_limits.name);
    }
  };
  check(storage, props_limits.max_storage_buffers_per_stage, "storage buffers");
  check(texels, props_limits.max_sampled_images_per_stage, "texel buffers");
  check(uniforms, props_limits.max_uniform_buffers_per_stage, "uniform buffers");

  try {
    std::vector<vk::DescriptorSetLayoutBinding> bindings;
    for (std::uint32_t i = 0; i < layout_.bindings.size(); ++i) {
      bindings.emplace_back(i, descriptor_type(layout_.bindings[i].kind), layout_.bindings[i].count,
                            vk::ShaderStageFlagBits::eCompute);
    }
    for (std::uint32_t i = 0; i < layout_.storage_images; ++i) {
      bindings.emplace_back(std::uint32_t(layout_.bindings.size()) + i,
                            vk::DescriptorType::eStorageImage, 1,
                            vk::ShaderStageFlagBits::eCompute);
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
