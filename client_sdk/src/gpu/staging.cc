#include "staging.h"

namespace omnisweep::gpu {

void flush_mapped(const Context& context, vk::DeviceMemory memory, bool coherent) {
  if (!coherent)
    context.device().flushMappedMemoryRanges(vk::MappedMemoryRange(memory, 0, VK_WHOLE_SIZE));
}

void invalidate_mapped(const Context& context, vk::DeviceMemory memory, bool coherent) {
  if (!coherent)
    context.device().invalidateMappedMemoryRanges(vk::MappedMemoryRange(memory, 0, VK_WHOLE_SIZE));
}

StagingPool::StagingPool(const Context& context) : context_(&context) {}

std::size_t StagingPool::bytes() const {
  std::size_t total = 0;
  for (const Slot* slot : {&upload_, &readback_}) {
    const std::lock_guard lock(slot->mutex);
    total += slot->size;
  }
  return total;
}

StagingPool::Lease StagingPool::lease(Slot& slot, MemoryUse use, std::size_t bytes) {
  std::unique_lock lock(slot.mutex);
  if (slot.size < bytes) {
    // Grown in powers of two from 1 MiB, so a sequence of growing transfers reallocates rarely.
    std::size_t size = std::size_t(1) << 20;
    while (size < bytes) size *= 2;
    slot.mapped = nullptr;
    slot.memory = nullptr;
    slot.buffer = nullptr;
    slot.size = 0;
    try {
      slot.buffer = vk::raii::Buffer(
          context_->device(), vk::BufferCreateInfo({}, size,
                                                   vk::BufferUsageFlagBits::eTransferSrc |
                                                       vk::BufferUsageFlagBits::eTransferDst));
      const auto req = slot.buffer.getMemoryRequirements();
      const MemoryChoice choice = context_->choose_memory(req.memoryTypeBits, use, size);
      slot.memory =
          vk::raii::DeviceMemory(context_->device(), vk::MemoryAllocateInfo(req.size, choice.type));
      slot.buffer.bindMemory(*slot.memory, 0);
      slot.mapped = slot.memory.mapMemory(0, VK_WHOLE_SIZE);
      slot.coherent = choice.coherent;
      slot.size = size;
    } catch (const vk::SystemError& e) {
      slot.memory = nullptr;
      slot.buffer = nullptr;
      throw GpuError("cannot allocate a " + std::to_string(size >> 20) + " MiB staging buffer on " +
                     context_->info().name + ": " + e.what());
    }
  }
  return Lease(std::move(lock), *context_, *slot.buffer, *slot.memory, slot.mapped, slot.coherent);
}

}  // namespace omnisweep::gpu
