#include "omnisweep/gpu/sequence.h"

#include <algorithm>
#include <cstdlib>
#include <string>

#include "omnisweep/gpu/command_log.h"

namespace omnisweep::gpu {

namespace {

// OMNISWEEP_PROFILE_KERNELS=1: every dispatch is timed as a stage of its own, named
// "<stage>/<kernel>" (same names summed), for finding where a frame's GPU time goes.
bool profile_kernels() {
  const char* v = std::getenv("OMNISWEEP_PROFILE_KERNELS");
  return v && std::string(v) == "1";
}

}  // namespace

Sequence::Sequence(const Context& context, std::uint32_t max_dispatches, std::uint32_t max_stages)
    : context_(&context),
      profile_kernels_(profile_kernels()),
      max_stages_(profile_kernels_ ? std::max(max_stages, 2 * max_dispatches) : max_stages) {
  const std::array<vk::DescriptorPoolSize, 4> sizes = {
      vk::DescriptorPoolSize(vk::DescriptorType::eStorageBuffer, max_dispatches * 24),
      vk::DescriptorPoolSize(vk::DescriptorType::eStorageImage, max_dispatches * 4),
      vk::DescriptorPoolSize(vk::DescriptorType::eUniformTexelBuffer, max_dispatches * 24),
      vk::DescriptorPoolSize(vk::DescriptorType::eUniformBuffer, max_dispatches * 4)};
  pool_ = vk::raii::DescriptorPool(context.device(),
                                   vk::DescriptorPoolCreateInfo({}, max_dispatches, sizes));
  command_pool_ = vk::raii::CommandPool(
      context.device(),
      vk::CommandPoolCreateInfo(vk::CommandPoolCreateFlagBits::eResetCommandBuffer,
                                context.queue_family()));
  commands_ = vk::raii::CommandBuffers(
      context.device(),
      vk::CommandBufferAllocateInfo(*command_pool_, vk::CommandBufferLevel::ePrimary, 1));
  if (context.info().timestamps) {
    queries_ = vk::raii::QueryPool(
        context.device(), vk::QueryPoolCreateInfo({}, vk::QueryType::eTimestamp, 2 * max_stages_));
  }
  fence_ = vk::raii::Fence(context.device(), vk::FenceCreateInfo());
}

void Sequence::begin() {
  pool_.reset();
  stage_names_.clear();
  timings_.clear();
  stage_open_ = false;
  const auto& cmd = commands_[0];
  cmd.reset();
  cmd.begin(vk::CommandBufferBeginInfo(vk::CommandBufferUsageFlagBits::eOneTimeSubmit));
  if (*queries_) cmd.resetQueryPool(*queries_, 0, 2 * max_stages_);
  recording_ = true;
}

void Sequence::dispatch(const Kernel& kernel, const std::vector<Binding>& bindings,
                        const void* push, std::size_t push_bytes,
                        std::array<std::uint32_t, 3> groups) {
  if (!recording_)
    throw GpuError("kernel " + kernel.name() + ": dispatch outside begin()/submit_and_wait()");
  const auto& layout = kernel.layout();
  const std::size_t buffer_bindings = layout.bindings.size();
  if (bindings.size() != buffer_bindings + layout.storage_images) {
    throw GpuError("kernel " + kernel.name() + ": expects " +
                   std::to_string(buffer_bindings + layout.storage_images) + " bindings, got " +
                   std::to_string(bindings.size()));
  }
  std::vector<vk::DescriptorImageInfo> image_infos;
  for (std::size_t b = buffer_bindings; b < bindings.size(); ++b) {
    if (!bindings[b].image) {
      throw GpuError("kernel " + kernel.name() + ": binding " + std::to_string(b) +
                     " takes a storage image");
    }
    image_infos.emplace_back(nullptr, bindings[b].image->view(), vk::ImageLayout::eGeneral);
  }
  if (push_bytes != layout.push_constant_bytes) {
    throw GpuError("kernel " + kernel.name() + ": push constants are " +
                   std::to_string(layout.push_constant_bytes) + " bytes, got " +
                   std::to_string(push_bytes));
  }
  const auto& limits = context_->info();
  for (int i = 0; i < 3; ++i) {
    if (groups[i] == 0 || groups[i] > limits.max_workgroup_count[i]) {
      throw GpuError("kernel " + kernel.name() + ": " + std::to_string(groups[i]) +
                     " workgroups in dimension " + std::to_string(i) + " (device limit " +
                     std::to_string(limits.max_workgroup_count[i]) + ")");
    }
  }
  std::vector<std::vector<vk::DescriptorBufferInfo>> infos(buffer_bindings);
  std::vector<std::vector<vk::BufferView>> views(buffer_bindings);
  std::uint64_t bound_bytes = 0;
  std::vector<const Buffer*> counted;  // a buffer bound twice (written, and read as texels) once
  for (std::size_t b = 0; b < buffer_bindings; ++b) {
    const BindingSlot& slot = layout.bindings[b];
    const bool texels = slot.kind == BindingKind::kTexelBuffer;
    const char* what = texels                                     ? " texel buffers"
                       : slot.kind == BindingKind::kUniformBuffer ? " uniform buffers"
                                                                  : " storage buffers";
    if (bindings[b].image || bindings[b].texel_format.has_value() != texels ||
        bindings[b].buffers.size() != slot.count) {
      throw GpuError("kernel " + kernel.name() + ": binding " + std::to_string(b) + " takes " +
                     std::to_string(slot.count) + what + ", got " +
                     std::to_string(bindings[b].buffers.size()) +
                     (bindings[b].image          ? " (a storage image)"
                      : bindings[b].texel_format ? " texel buffers"
                                                 : " buffers"));
    }
    const std::uint64_t range = slot.kind == BindingKind::kStorageBuffer
                                    ? limits.max_storage_buffer_range
                                : slot.kind == BindingKind::kUniformBuffer
                                    ? limits.max_uniform_buffer_range
                                    : ~std::uint64_t(0);  // texel_view checks its own limit
    for (const Buffer* buffer : bindings[b].buffers) {
      if (buffer->size() > range) {
        throw GpuError("kernel " + kernel.name() + ": binding " + std::to_string(b) + " is " +
                       std::to_string(buffer->size()) + " bytes, over the device's " +
                       (slot.kind == BindingKind::kStorageBuffer ? "maxStorageBufferRange"
                                                                 : "maxUniformBufferRange") +
                       " of " + std::to_string(range) + " bytes");
      }
      if (texels) {
        views[b].push_back(buffer->texel_view(*bindings[b].texel_format));
      } else {
        infos[b].emplace_back(buffer->handle(), 0, VK_WHOLE_SIZE);
      }
      if (std::find(counted.begin(), counted.end(), buffer) == counted.end()) {
        counted.push_back(buffer);
        bound_bytes += buffer->size();
      }
    }
  }
  // Everything is checked: allocate the set and hand it to the pool at once (the pool frees it
  // on the next begin(); freeing sets one by one is not allowed for this pool).
  const vk::DescriptorSetLayout set_layout = kernel.set_layout();
  vk::raii::DescriptorSets sets(context_->device(),
                                vk::DescriptorSetAllocateInfo(*pool_, set_layout));
  const vk::DescriptorSet set = sets[0].release();
  std::vector<vk::WriteDescriptorSet> writes;
  for (std::size_t b = 0; b < buffer_bindings; ++b) {
    const vk::DescriptorType type = descriptor_type(layout.bindings[b].kind);
    if (type == vk::DescriptorType::eUniformTexelBuffer) {
      writes.emplace_back(set, std::uint32_t(b), 0, type, nullptr, nullptr, views[b]);
    } else {
      writes.emplace_back(set, std::uint32_t(b), 0, type, nullptr, infos[b]);
    }
  }
  for (std::size_t i = 0; i < image_infos.size(); ++i) {
    writes.emplace_back(set, std::uint32_t(buffer_bindings + i), 0, 1,
                        vk::DescriptorType::eStorageImage, &image_infos[i]);
  }
  context_->device().updateDescriptorSets(writes, nullptr);
  const auto& cmd = commands_[0];
  cmd.bindPipeline(vk::PipelineBindPoint::eCompute, kernel.pipeline());
  cmd.bindDescriptorSets(vk::PipelineBindPoint::eCompute, kernel.pipeline_layout(), 0, set,
                         nullptr);
  if (push_bytes) {
    const vk::ArrayProxy<const std::uint8_t> bytes(std::uint32_t(push_bytes),
                                                   static_cast<const std::uint8_t*>(push));
    cmd.pushConstants<std::uint8_t>(kernel.pipeline_layout(), vk::ShaderStageFlagBits::eCompute, 0,
                                    bytes);
  }
  std::string stage;
  if (profile_kernels_) {
    stage = stage_open_ ? stage_names_.back() : std::string();
    begin_stage(stage + "/" + kernel.name());
  }
  cmd.dispatch(groups[0], groups[1], groups[2]);
  if (profile_kernels_) begin_stage(stage);
  if (CommandLog* log = context_->command_log()) {
    for (std::size_t b = buffer_bindings; b < bindings.size(); ++b)
      bound_bytes += bindings[b].image->bytes();
    const auto& local = layout.local_size;
    log->add_dispatch({.kernel = kernel.name(),
                       .stage = current_stage(),
                       .groups = groups,
                       .invocations = std::uint64_t(groups[0]) * groups[1] * groups[2] * local[0] *
                                      local[1] * local[2],
                       .bound_bytes = bound_bytes});
  }
}

std::string Sequence::current_stage() const {
  return stage_open_ ? stage_names_.back() : std::string();
}

void Sequence::barrier() {
  const vk::MemoryBarrier memory(
      vk::AccessFlagBits::eShaderWrite | vk::AccessFlagBits::eTransferWrite,
      vk::AccessFlagBits::eShaderRead | vk::AccessFlagBits::eShaderWrite |
          vk::AccessFlagBits::eTransferRead | vk::AccessFlagBits::eTransferWrite);
  const auto stages =
      vk::PipelineStageFlagBits::eComputeShader | vk::PipelineStageFlagBits::eTransfer;
  commands_[0].pipelineBarrier(stages, stages, {}, memory, nullptr, nullptr);
  if (CommandLog* log = context_->command_log()) log->add_barrier(current_stage());
}

void Sequence::copy(const Buffer& source, Buffer& destination, vk::DeviceSize bytes,
                    vk::DeviceSize source_offset, vk::DeviceSize destination_offset) {
  if (source_offset + bytes > source.size() || destination_offset + bytes > destination.size()) {
    throw GpuError("GPU copy of " + std::to_string(bytes) + " bytes exceeds its buffers");
  }
  commands_[0].copyBuffer(source.handle(), destination.handle(),
                          vk::BufferCopy(source_offset, destination_offset, bytes));
}

void Sequence::fill(Buffer& buffer, std::uint32_t pattern) {
  commands_[0].fillBuffer(buffer.handle(), 0, VK_WHOLE_SIZE, pattern);
}

void Sequence::begin_stage(const std::string& name) {
  if (stage_open_) end_stage();
  if (stage_names_.size() >= max_stages_) throw GpuError("too many timed stages in one sequence");
  if (*queries_) {
    commands_[0].writeTimestamp(vk::PipelineStageFlagBits::eBottomOfPipe, *queries_,
                                std::uint32_t(2 * stage_names_.size()));
  }
  stage_names_.push_back(name);
  stage_open_ = true;
}

void Sequence::end_stage() {
  if (!stage_open_) return;
  if (*queries_) {
    commands_[0].writeTimestamp(vk::PipelineStageFlagBits::eBottomOfPipe, *queries_,
                                std::uint32_t(2 * stage_names_.size() - 1));
  }
  stage_open_ = false;
}

void Sequence::submit_and_wait() {
  if (!recording_) throw GpuError("submit_and_wait() without begin()");
  // The wait is charged to the last stage this submission recorded.
  if (CommandLog* log = context_->command_log())
    log->add_round_trip(stage_names_.empty() ? std::string() : stage_names_.back());
  end_stage();
  const auto& cmd = commands_[0];
  cmd.end();
  recording_ = false;
  context_->device().resetFences(*fence_);
  const vk::CommandBuffer raw = *cmd;
  context_->submit(raw, *fence_);
  if (context_->device().waitForFences(*fence_, VK_TRUE, UINT64_MAX) != vk::Result::eSuccess) {
    throw GpuError("waiting for the GPU failed");
  }
  timings_.clear();
  if (!*queries_ || stage_names_.empty()) return;
  const auto count = std::uint32_t(2 * stage_names_.size());
  const auto [result, stamps] = queries_.getResults<std::uint64_t>(
      0, count, count * sizeof(std::uint64_t), sizeof(std::uint64_t),
      vk::QueryResultFlagBits::e64 | vk::QueryResultFlagBits::eWait);
  if (result != vk::Result::eSuccess) return;
  for (std::size_t i = 0; i < stage_names_.size(); ++i) {
    const double ms =
        double(stamps[2 * i + 1] - stamps[2 * i]) * context_->info().timestamp_period_ns * 1e-6;
    auto it = std::find_if(timings_.begin(), timings_.end(),
                           [&](const auto& t) { return t.first == stage_names_[i]; });
    if (it == timings_.end()) {
      timings_.emplace_back(stage_names_[i], ms);
    } else {
      it->second += ms;
    }
  }
}

std::vector<std::pair<std::string, double>> Sequence::stage_ms() const { return timings_; }

}  // namespace omnisweep::gpu
