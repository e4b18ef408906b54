// Owning, move-only images and cheap non-owning views (basalt's ManagedImage / Image split).
//
// The pixel format is part of the type: the sample type and the number of channels (Rgb8Image,
// Gray8Image, FloatImage, ...), so a grey mask cannot be passed where colour is expected and no
// function checks channels() at run time. Pixels are interleaved, rows are contiguous, and
// (x, y) = (0, 0) is the top-left pixel. Colour images in omnisweep are always RGB (never BGR):
// the OpenCV edge converts on I/O.
#pragma once

#include <algorithm>
#include <cassert>
#include <cstddef>
#include <cstdint>
#include <span>
#include <type_traits>
#include <variant>
#include <vector>

namespace omnisweep {

// A view of width x height pixels of `Channels` samples of T each (T const for a read-only view).
// Functions take views at their boundaries (a camera's image, a panorama's distance), so callers
// pass an owned Image, a part of a larger buffer or a decoded frame alike.
template <typename T, int Channels = 1>
class ImageView {
  static_assert(Channels >= 1);

 public:
  using value_type = std::remove_const_t<T>;

  ImageView() = default;
  ImageView(T* data, int width, int height) : data_(data), width_(width), height_(height) {}
  // A writable view is also a read-only one.
  template <typename U>
  requires std::is_same_v<const U, T> ImageView(
      ImageView<U, Channels> other)  // NOLINT(google-explicit-constructor)
      : ImageView(other.data(), other.width(), other.height()) {}

  int width() const { return width_; }
  int height() const { return height_; }
  static constexpr int channels() { return Channels; }
  std::size_t size() const { return std::size_t(width_) * height_ * Channels; }
  bool empty() const { return size() == 0; }
  T* data() const { return data_; }
  std::span<T> pixels() const { return {data_, size()}; }

  T& operator()(int x, int y, int c = 0) const {
    assert(x >= 0 && x < width_ && y >= 0 && y < height_ && c >= 0 && c < Channels);
    return data_[(std::size_t(y) * width_ + x) * Channels + c];
  }
  T* row(int y) const { return data_ + std::size_t(y) * width_ * Channels; }
  bool contains(int x, int y) const { return x >= 0 && y >= 0 && x < width_ && y < height_; }

 private:
  T* data_ = nullptr;
  int width_ = 0;
  int height_ = 0;
};

// An owned image of width x height pixels of `Channels` samples of T each, zero-filled unless
// made with filled().
template <typename T, int Channels = 1>
class Image {
  static_assert(Channels >= 1);

 public:
  using value_type = T;

  Image() = default;
  Image(int width, int height)
      : pixels_(std::size_t(width) * height * Channels, T{}), width_(width), height_(height) {
    assert(width >= 0 && height >= 0);
  }
  // Every sample set to `value` (a named constructor: Image(w, h, v) would read as a channel
  // count).
  static Image filled(int width, int height, T value) {
    Image image(width, height);
    std::fill(image.pixels_.begin(), image.pixels_.end(), value);
    return image;
  }
  Image(Image&&) noexcept = default;
  Image& operator=(Image&&) noexcept = default;
  Image(const Image&) = delete;
  Image& operator=(const Image&) = delete;

  // An explicit deep copy, since copies of full frames should be visible in code.
  Image clone() const {
    Image copy;
    copy.pixels_ = pixels_;
    copy.width_ = width_;
    copy.height_ = height_;
    return copy;
  }
  // A deep copy of a view's pixels.
  static Image copy_of(ImageView<const T, Channels> view) {
    Image copy(view.width(), view.height());
    std::copy(view.pixels().begin(), view.pixels().end(), copy.pixels_.begin());
    return copy;
  }

  int width() const { return width_; }
  int height() const { return height_; }
  static constexpr int channels() { return Channels; }
  std::size_t size() const { return pixels_.size(); }
  bool empty() const { return pixels_.empty(); }
  T* data() { return pixels_.data(); }
  const T* data() const { return pixels_.data(); }
  std::span<T> pixels() { return pixels_; }
  std::span<const T> pixels() const { return pixels_; }

  T& operator()(int x, int y, int c = 0) { return pixels_[index(x, y, c)]; }
  const T& operator()(int x, int y, int c = 0) const { return pixels_[index(x, y, c)]; }
  bool contains(int x, int y) const { return x >= 0 && y >= 0 && x < width_ && y < height_; }

  ImageView<T, Channels> view() { return {pixels_.data(), width_, height_}; }
  ImageView<const T, Channels> view() const { return {pixels_.data(), width_, height_}; }
  // An image is passed where a read-only view is taken.
  operator ImageView<const T, Channels>() const { return view(); }  // NOLINT

 private:
  std::size_t index(int x, int y, int c) const {
    assert(x >= 0 && x < width_ && y >= 0 && y < height_ && c >= 0 && c < Channels);
    return (std::size_t(y) * width_ + x) * Channels + c;
  }

  std::vector<T> pixels_;
  int width_ = 0;
  int height_ = 0;
};

using Rgb8Image = Image<std::uint8_t, 3>;   // RGB, 0..255
using Gray8Image = Image<std::uint8_t, 1>;  // masks, quantised levels
using Rgb16Image = Image<std::uint16_t, 3>;
using FloatImage = Image<float, 1>;  // distance, inverse distance, confidence
using RgbFloatImage = Image<float, 3>;

using Rgb8View = ImageView<const std::uint8_t, 3>;
using Gray8View = ImageView<const std::uint8_t, 1>;
using FloatView = ImageView<const float, 1>;

// A colour image as it was stored: 8-bit, 16-bit or float samples, always RGB order.
// 16-bit samples span 0..65535 and float samples 0..1 at full scale.
using AnyImage = std::variant<Rgb8Image, Rgb16Image, RgbFloatImage>;

int width_of(const AnyImage& image);
int height_of(const AnyImage& image);
const char* depth_name(const AnyImage& image);  // "8-bit", "16-bit" or "float"

// Converts to 8-bit (rounded, clamped) or to float on the 0..255 scale the matching cost uses
// (ALGORITHM.md §3 step 3), keeping 16-bit and float precision.
Rgb8Image to_rgb8(const AnyImage& image);
// 1 / x per value where x > 0, else 0: distance (m) <-> inverse distance (m^-1), 0 = no value.
FloatImage reciprocal_or_zero(FloatView image);
RgbFloatImage to_rgb_float255(const AnyImage& image);

// Read-only views of owned images, in order (for functions that take views of every camera).
template <typename T, int Channels>
std::vector<ImageView<const T, Channels>> views(const std::vector<Image<T, Channels>>& images) {
  return {images.begin(), images.end()};
}

}  // namespace omnisweep
