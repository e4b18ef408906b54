// Owning, move-only images and cheap non-owning views (basalt's ManagedImage / Image split).
//
// Pixels are interleaved, rows are contiguous, and (x, y) = (0, 0) is the top-left pixel.
// Colour images in omnisweep are always RGB (never BGR): the OpenCV edge converts on I/O.
#pragma once

#include <cassert>
#include <cstddef>
#include <cstdint>
#include <span>
#include <variant>
#include <vector>

namespace omnisweep {

template <typename T>
class ImageView {
 public:
  ImageView() = default;
  ImageView(T* data, int width, int height, int channels)
      : data_(data), width_(width), height_(height), channels_(channels) {}

  int width() const { return width_; }
  int height() const { return height_; }
  int channels() const { return channels_; }
  std::size_t size() const { return std::size_t(width_) * height_ * channels_; }
  bool empty() const { return size() == 0; }
  T* data() const { return data_; }
  std::span<T> pixels() const { return {data_, size()}; }

  T& operator()(int x, int y, int c = 0) const {
    assert(x >= 0 && x < width_ && y >= 0 && y < height_ && c >= 0 && c < channels_);
    return data_[(std::size_t(y) * width_ + x) * channels_ + c];
  }
  T* row(int y) const { return data_ + std::size_t(y) * width_ * channels_; }
  bool contains(int x, int y) const { return x >= 0 && y >= 0 && x < width_ && y < height_; }

 private:
  T* data_ = nullptr;
  int width_ = 0;
  int height_ = 0;
  int channels_ = 0;
};

template <typename T>
class Image {
 public:
  using value_type = T;

  Image() = default;
  Image(int width, int height, int channels, T fill = T{})
      : pixels_(std::size_t(width) * height * channels, fill),
        width_(width),
        height_(height),
        channels_(channels) {
    assert(width >= 0 && height >= 0 && channels > 0);
  }
  Image(Image&&) noexcept = default;
  Image& operator=(Image&&) noexcept = default;
  Image(const Image&) = delete;
  Image& operator=(const Image&) = delete;

  // An explicit deep copy, since copies of full frames should be visible in code.
  Image clone() const {
    Image copy(width_, height_, channels_);
    copy.pixels_ = pixels_;
    return copy;
  }

  int width() const { return width_; }
  int height() const { return height_; }
  int channels() const { return channels_; }
  std::size_t size() const { return pixels_.size(); }
  bool empty() const { return pixels_.empty(); }
  T* data() { return pixels_.data(); }
  const T* data() const { return pixels_.data(); }
  std::span<T> pixels() { return pixels_; }
  std::span<const T> pixels() const { return pixels_; }

  T& operator()(int x, int y, int c = 0) { return pixels_[index(x, y, c)]; }
  const T& operator()(int x, int y, int c = 0) const { return pixels_[index(x, y, c)]; }
  bool contains(int x, int y) const { return x >= 0 && y >= 0 && x < width_ && y < height_; }

  ImageView<T> view() { return {pixels_.data(), width_, height_, channels_}; }
  ImageView<const T> view() const { return {pixels_.data(), width_, height_, channels_}; }

 private:
  std::size_t index(int x, int y, int c) const {
    assert(x >= 0 && x < width_ && y >= 0 && y < height_ && c >= 0 && c < channels_);
    return (std::size_t(y) * width_ + x) * channels_ + c;
  }

  std::vector<T> pixels_;
  int width_ = 0;
  int height_ = 0;
  int channels_ = 0;
};

using Rgb8Image = Image<std::uint8_t>;   // 3 channels, RGB, 0..255
using Gray8Image = Image<std::uint8_t>;  // 1 channel
using FloatImage = Image<float>;

// A colour image as it was stored: 8-bit, 16-bit or float samples, always RGB order.
// 16-bit samples span 0..65535 and float samples 0..1 at full scale.
using AnyImage = std::variant<Image<std::uint8_t>, Image<std::uint16_t>, Image<float>>;

int width_of(const AnyImage& image);
int height_of(const AnyImage& image);
const char* depth_name(const AnyImage& image);  // "8-bit", "16-bit" or "float"

// Converts to 8-bit (rounded, clamped) or to float on the 0..255 scale the matching cost uses
// (ALGORITHM.md §3 step 3), keeping 16-bit and float precision.
Rgb8Image to_rgb8(const AnyImage& image);
// 1 / x per value where x > 0, else 0: distance (m) <-> inverse distance (m^-1), 0 = no value.
FloatImage reciprocal_or_zero(const FloatImage& image);
FloatImage to_rgb_float255(const AnyImage& image);

}  // namespace omnisweep
