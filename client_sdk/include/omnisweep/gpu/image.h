// A 2D storage image with its memory and view, owned (move-only). It rests in
// VK_IMAGE_LAYOUT_GENERAL, where kernels read and write it (imageLoad / imageStore); uploads and
// downloads move it to the transfer layouts and back.
#pragma once

#include <cstdint>
#include <vector>

#include "omnisweep/gpu/context.h"
#include "omnisweep/gpu/vulkan.h"

namespace omnisweep::gpu {

enum class ImageFormat {
  kRgba8,  // 4 x 8-bit unsigned normalised (GLSL rgba8), 4 bytes per texel
  kR32f,   // one float (GLSL r32f), 4 bytes per texel
};

class Image {
 public:
  // Throws GpuError for an empty size or one the device does not support for storage images.
  Image(Context& context, int width, int height, ImageFormat format);
  ~Image();
  Image(Image&&) noexcept;
  Image& operator=(Image&&) noexcept;
  Image(const Image&) = delete;
  Image& operator=(const Image&) = delete;

  int width() const { return width_; }
  int height() const { return height_; }
  ImageFormat format() const { return format_; }
  std::size_t bytes() const { return std::size_t(width_) * height_ * 4; }
  vk::Image handle() const { return *image_; }
  vk::ImageView view() const { return *view_; }

  // Texels row by row, 4 bytes each (RGBA8: r in the lowest byte); sizes must equal bytes().
  void upload(const void* data, std::size_t bytes);
  void download(void* data, std::size_t bytes) const;

 private:
  Context* context_;
  int width_;
  int height_;
  ImageFormat format_;
  vk::raii::Image image_{nullptr};
  vk::raii::DeviceMemory memory_{nullptr};
  vk::raii::ImageView view_{nullptr};
};

}  // namespace omnisweep::gpu
