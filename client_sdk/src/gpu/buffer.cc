#include "omnisweep/gpu/buffer.h"

#include <cstring>
#include <iterator>

#include "omnisweep/gpu/command_log.h"
#include "staging.h"

namespace omnisweep::gpu {
namespace {

constexpr auto kUsage =
    vk::BufferUsageFlagBits::eStorageBuffer | vk::BufferUsageFlagBits::eUniformTexelBuffer |
    vk::BufferUsageFlagBits::eUniformBuffer | vk::BufferUsageFlagBits::eTransferSrc |
    vk::BufferUsageFlagBits::eTransferDst;

// Each TexelFormat's Vulkan format and size, in the enum's order.
struct TexelFormatInfo {
  vk::Format format;
  std::uint32_t bytes;
};
constexpr TexelFormatInfo kTexelFormats[] = {{vk::Format::eR32Uint, 4},
                                             {vk::Format::eR32G32B32A32Uint, 16},
                                             {vk::Format::eR32Sfloat, 4},
                                             {vk::Format::eR16Sfloat, 2},
                                             {vk::Format::eR16G16B16A16Sfloat, 8},
                                             {vk::Format::eR32G32B32A32Sfloat, 16}};

static_assert(std::size(kTexelFormats) == std::size_t(TexelFormat::kRgba32Float) + 1,
              "one entry per TexelFormat");

const TexelFormatInfo& info_of(TexelFormat format) {
  return kTexelFormats[static_cast<std::size_t>(format)];
}

}  // namespace

std::uint32_t texel_bytes(TexelFormat format) { return info_of(format).bytes; }

Buffer::Buffer(Context& context, vk::DeviceSize bytes) : context_(&context), size_(bytes) {
  if (bytes == 0) throw GpuError("cannot create an empty GPU buffer");
  try {
    buffer_ = vk::raii::Buffer(context.device(), vk::BufferCreateInfo({}, bytes, kUsage));
    const auto req = buffer_.getMemoryRequirements();
    memory_ = context.choose_memory(req.memoryTypeBits, MemoryUse::kDevice, req.size);
    device_memory_ =
        vk::raii::DeviceMemory(context.device(), vk::MemoryAllocateInfo(req.size, memory_.type));
    buffer_.bindMemory(*device_memory_, 0);
    if (memory_.mapped) mapped_ = device_memory_.mapMemory(0, VK_WHOLE_SIZE);
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
      memory_(other.memory_),
      buffer_(std::move(other.buffer_)),
      device_memory_(std::move(other.device_memory_)),
      mapped_(std::exchange(other.mapped_, nullptr)),
      views_mutex_(std::move(other.views_mutex_)),
      views_(std::move(other.views_)) {
  other.views_mutex_ = std::make_unique<std::mutex>();
}

Buffer& Buffer::operator=(Buffer&& other) noexcept {
  if (this != &other) {
    views_.clear();  // before the buffer they view
    if (*buffer_) context_->track_allocation(-std::int64_t(size_));
    context_ = other.context_;
    size_ = other.size_;
    memory_ = other.memory_;
    buffer_ = std::move(other.buffer_);
    device_memory_ = std::move(other.device_memory_);
    mapped_ = std::exchange(other.mapped_, nullptr);
    views_ = std::move(other.views_);
    other.views_.clear();
  }
  return *this;
}

vk::BufferView Buffer::texel_view(TexelFormat format) const {
  const std::lock_guard lock(*views_mutex_);
  for (const auto& [f, view] : views_) {
    if (f == format) return *view;
  }
  const std::uint64_t texels = size_ / texel_bytes(format);
  if (texels == 0 || texels > context_->info().max_texel_buffer_elements) {
    throw GpuError("a texel view of " + std::to_string(texels) + " texels is outside (0, " +
                   std::to_string(context_->info().max_texel_buffer_elements) +
                   "], the device's maxTexelBufferElements");
  }
  try {
    views_.emplace_back(
        format, vk::raii::BufferView(context_->device(),
                                     vk::BufferViewCreateInfo({}, *buffer_, info_of(format).format,
                                                              0, texels * texel_bytes(format))));
  } catch (const vk::SystemError& e) {
    throw GpuError(std::string("cannot create a texel view of a GPU buffer: ") + e.what());
  }
  return *views_.back().second;
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
  if (CommandLog* log = context_->command_log()) log->add_transfer(bytes, true);
  if (mapped_) {  // host writes to mapped device memory are fast, even uncached (write-combined)
    std::memcpy(static_cast<char*>(mapped_) + offset, data, bytes);
    flush_mapped(*context_, *device_memory_, memory_.coherent);
    return;
  }
  const auto staging = context_->staging().upload(bytes);
  std::memcpy(staging.data(), data, bytes);
  staging.flush();
  context_->run_commands([&](const vk::raii::CommandBuffer& cmd) {
    cmd.copyBuffer(staging.buffer(), *buffer_, vk::BufferCopy(0, offset, bytes));
  });
}

void Buffer::download(void* data, std::size_t bytes, std::size_t offset) const {
  check_range(bytes, offset);
  if (bytes == 0) return;
  if (CommandLog* log = context_->command_log()) log->add_transfer(bytes, false);
  if (mapped_ && memory_.cached) {  // reads of uncached device memory go through staging instead
    invalidate_mapped(*context_, *device_memory_, memory_.coherent);
    std::memcpy(data, static_cast<const char*>(mapped_) + offset, bytes);
    return;
  }
  const auto staging = context_->staging().readback(bytes);
  context_->run_commands([&](const vk::raii::CommandBuffer& cmd) {
    cmd.copyBuffer(*buffer_, staging.buffer(), vk::BufferCopy(offset, 0, bytes));
  });
  staging.invalidate();
  std::memcpy(data, staging.data(), bytes);
}

}  // namespace omnisweep::gpu
