#include "omnisweep/gpu/image.h"

#include <cstring>

#include "omnisweep/gpu/command_log.h"
#include "staging.h"

namespace omnisweep::gpu {
namespace {

vk::Format vk_format(ImageFormat format) {
  return format == ImageFormat::kRgba8 ? vk::Format::eR8G8B8A8Unorm : vk::Format::eR32Sfloat;
}

const vk::ImageSubresourceRange kColor(vk::ImageAspectFlagBits::eColor, 0, 1, 0, 1);

// Moves `image` between GENERAL (its resting layout) and a transfer layout around a copy.
void transition(const vk::raii::CommandBuffer& cmd, vk::Image image, vk::ImageLayout from,
                vk::ImageLayout to) {
  const auto access = vk::AccessFlagBits::eShaderRead | vk::AccessFlagBits::eShaderWrite |
                      vk::AccessFlagBits::eTransferRead | vk::AccessFlagBits::eTransferWrite;
  const vk::ImageMemoryBarrier barrier(access, access, from, to, VK_QUEUE_FAMILY_IGNORED,
                                       VK_QUEUE_FAMILY_IGNORED, image, kColor);
  const auto stages =
      vk::PipelineStageFlagBits::eComputeShader | vk::PipelineStageFlagBits::eTransfer;
  cmd.pipelineBarrier(stages, stages, {}, nullptr, nullptr, barrier);
}

}  // namespace

Image::Image(Context& context, int width, int height, ImageFormat format)
    : context_(&context), width_(width), height_(height), format_(format) {
  if (width <= 0 || height <= 0) throw GpuError("cannot create an empty GPU image");
  const auto support = context.physical_device().getFormatProperties(vk_format(format));
  if (!(support.optimalTilingFeatures & vk::FormatFeatureFlagBits::eStorageImage)) {
    throw GpuError(context.info().name + " cannot use this image format as a storage image");
  }
  try {
    image_ = vk::raii::Image(
        context.device(),
        vk::ImageCreateInfo(
            {}, vk::ImageType::e2D, vk_format(format), vk::Extent3D(width, height, 1), 1, 1,
            vk::SampleCountFlagBits::e1, vk::ImageTiling::eOptimal,
            vk::ImageUsageFlagBits::eStorage | vk::ImageUsageFlagBits::eTransferSrc |
                vk::ImageUsageFlagBits::eTransferDst));
    const auto req = image_.getMemoryRequirements();
    memory_ = vk::raii::DeviceMemory(
        context.device(),
        vk::MemoryAllocateInfo(
            req.size,
            context.choose_memory(req.memoryTypeBits, MemoryUse::kDevice, req.size).type));
    image_.bindMemory(*memory_, 0);
    view_ = vk::raii::ImageView(context.device(),
                                vk::ImageViewCreateInfo({}, *image_, vk::ImageViewType::e2D,
                                                        vk_format(format), {}, kColor));
  } catch (const vk::SystemError& e) {
    throw GpuError("cannot create a " + std::to_string(width) + "x" + std::to_string(height) +
                   " GPU image on " + context.info().name + ": " + e.what());
  }
  // Once into GENERAL, where it stays.
  context.run_commands([&](const vk::raii::CommandBuffer& cmd) {
    const vk::ImageMemoryBarrier barrier(
        {}, vk::AccessFlagBits::eShaderRead | vk::AccessFlagBits::eShaderWrite,
        vk::ImageLayout::eUndefined, vk::ImageLayout::eGeneral, VK_QUEUE_FAMILY_IGNORED,
        VK_QUEUE_FAMILY_IGNORED, *image_, kColor);
    cmd.pipelineBarrier(vk::PipelineStageFlagBits::eTopOfPipe,
                        vk::PipelineStageFlagBits::eComputeShader, {}, nullptr, nullptr, barrier);
  });
  context_->track_allocation(std::int64_t(bytes()));
}

Image::~Image() {
  if (*image_) context_->track_allocation(-std::int64_t(bytes()));
}

Image::Image(Image&& other) noexcept
    : context_(other.context_),
      width_(other.width_),
      height_(other.height_),
      format_(other.format_),
      image_(std::move(other.image_)),
      memory_(std::move(other.memory_)),
      view_(std::move(other.view_)) {}

Image& Image::operator=(Image&& other) noexcept {
  if (this != &other) {
    if (*image_) context_->track_allocation(-std::int64_t(bytes()));
    context_ = other.context_;
    width_ = other.width_;
    height_ = other.height_;
    format_ = other.format_;
    view_ = std::move(other.view_);
    image_ = std::move(other.image_);
    memory_ = std::move(other.memory_);
  }
  return *this;
}

void Image::upload(const void* data, std::size_t size) {
  if (size != bytes()) {
    throw GpuError("GPU image upload of " + std::to_string(size) + " bytes, the image holds " +
                   std::to_string(bytes()));
  }
  if (CommandLog* log = context_->command_log()) log->add_transfer(size, true);
  const auto staging = context_->staging().upload(size);
  std::memcpy(staging.data(), data, size);
  staging.flush();
  context_->run_commands([&](const vk::raii::CommandBuffer& cmd) {
    transition(cmd, *image_, vk::ImageLayout::eGeneral, vk::ImageLayout::eTransferDstOptimal);
    cmd.copyBufferToImage(staging.buffer(), *image_, vk::ImageLayout::eTransferDstOptimal,
                          vk::BufferImageCopy(0, 0, 0, {vk::ImageAspectFlagBits::eColor, 0, 0, 1},
                                              {0, 0, 0}, vk::Extent3D(width_, height_, 1)));
    transition(cmd, *image_, vk::ImageLayout::eTransferDstOptimal, vk::ImageLayout::eGeneral);
  });
}

void Image::download(void* data, std::size_t size) const {
  if (size != bytes()) {
    throw GpuError("GPU image download of " + std::to_string(size) + " bytes, the image holds " +
                   std::to_string(bytes()));
  }
  if (CommandLog* log = context_->command_log()) log->add_transfer(size, false);
  const auto staging = context_->staging().readback(size);
  context_->run_commands([&](const vk::raii::CommandBuffer& cmd) {
    transition(cmd, *image_, vk::ImageLayout::eGeneral, vk::ImageLayout::eTransferSrcOptimal);
    cmd.copyImageToBuffer(*image_, vk::ImageLayout::eTransferSrcOptimal, staging.buffer(),
                          vk::BufferImageCopy(0, 0, 0, {vk::ImageAspectFlagBits::eColor, 0, 0, 1},
                                              {0, 0, 0}, vk::Extent3D(width_, height_, 1)));
    transition(cmd, *image_, vk::ImageLayout::eTransferSrcOptimal, vk::ImageLayout::eGeneral);
  });
  staging.invalidate();
  std::memcpy(data, staging.data(), size);
}

}  // namespace omnisweep::gpu
