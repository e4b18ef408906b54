#include "omnisweep/gpu/buffer.h"

#include <cstring>

namespace omnisweep::gpu {
namespace {

constexpr auto kUsage = vk::BufferUsageFlagBits::eStorageBuffer |
                        vk::BufferUsageFlagBits::eTransferSrc |
                        vk::BufferUsageFlagBits::eTransferDst;
constexpr auto kHostAccess =
    vk::MemoryPropertyFlagBits::eHostVisible | vk::MemoryPropertyFlagBits::eHostCoherent;

// A host-visible buffer for copies to and from device-only memory.
struct Staging {
  vk::raii::Buffer buffer{nullptr};
  vk::raii::DeviceMemory memory{nullptr};
  void* mapped = nullptr;

  Staging(const Context& context, vk::DeviceSize bytes) {
    buffer = vk::raii::Buffer(context.device(), vk::BufferCreateInfo({}, bytes, kUsage));
    const auto req = buffer.getMemoryRequirements();
    memory = vk::raii::DeviceMemory(
        context.device(), vk::MemoryAllocateInfo(
                              req.size, context.find_memory_type(req.memoryTypeBits, kHostAccess)));
    buffer.bindMemory(*memory, 0);
    mapped = memory.mapMemory(0, bytes);
  }
};

}  // namespace

Buffer::Buffer(Context& context, vk::DeviceSize bytes) : context_(&context), size_(bytes) {
  if (bytes == 0) throw GpuError("cannot create an empty GPU buffer");
  try {
    buffer_ = vk::raii::Buffer(context.device(), vk::BufferCreateInfo({}, bytes, kUsage));
    const auto req = buffer_.getMemoryRequirements();
    const std::uint32_t type = context.find_memory_type(
        req.memoryTypeBits, vk::MemoryPropertyFlagBits::eDeviceLocal, kHostAccess);
    memory_ = vk::raii::DeviceMemory(context.device(), vk::MemoryAllocateInfo(req.size, type));
    buffer_.bindMemory(*memory_, 0);
    if (context.memory_type_has(type, kHostAccess)) mapped_ = memory_.mapMemory(0, bytes);
  } catch (const vk::SystemError& e) {
    throw GpuError("cannot allocate a GPU buffer of " + std::to_string(bytes >> 20) + " MiB on " +
                   context.info().name + ": " + e.what());
  }
  context_->track_allocation(std::int64_t(size_));
}

Buffer::~Buffer() {
  if (*buffer_) context_->track_allocation(-std::int64_t(size_));
}

Buffer::Buffer(Buffer&& other) noexcept
    : context_(other.context_),
      size_(other.size_),
      buffer_(std::move(other.buffer_)),
      memory_(std::move(other.memory_)),
      mapped_(std::exchange(other.mapped_, nullptr)) {}

Buffer& Buffer::operator=(Buffer&& other) noexcept {
  if (this != &other) {
    if (*buffer_) context_->track_allocation(-std::int64_t(size_));
    context_ = other.context_;
    size_ = other.size_;
    buffer_ = std::move(other.buffer_);
    memory_ = std::move(other.memory_);
    mapped_ = std::exchange(other.mapped_, nullptr);
  }
  return *this;
}

void Buffer::check_range(std::size_t bytes, std::size_t offset) const {
  if (offset > size_ || bytes > size_ - offset) {
    throw GpuError("GPU buffer access of " + std::to_string(bytes) + " bytes at " +
                   std::to_string(offset) + " exceeds its size " + std::to_string(size_));
  }
}

void Buffer::upload(const void* data, std::size_t bytes, std::size_t offset) {
  check_range(bytes, offset);
  if (bytes == 0) return;
  if (mapped_) {
    std::memcpy(static_cast<char*>(mapped_) + offset, data, bytes);
    return;
  }
  Staging staging(*context_, bytes);
  std::memcpy(staging.mapped, data, bytes);
  context_->run_commands([&](const vk::raii::CommandBuffer& cmd) {
    cmd.copyBuffer(*staging.buffer, *buffer_, vk::BufferCopy(0, offset, bytes));
  });
}

void Buffer::download(void* data, std::size_t bytes, std::size_t offset) const {
  check_range(bytes, offset);
  if (bytes == 0) return;
  if (mapped_) {
    std::memcpy(data, static_cast<const char*>(mapped_) + offset, bytes);
    return;
  }
  Staging staging(*context_, bytes);
  context_->run_commands([&](const vk::raii::CommandBuffer& cmd) {
    cmd.copyBuffer(*buffer_, *staging.buffer, vk::BufferCopy(offset, 0, bytes));
  });
  std::memcpy(data, staging.mapped, bytes);
}

}  // namespace omnisweep::gpu
