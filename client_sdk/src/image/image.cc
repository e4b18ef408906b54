#include "omnisweep/image/image.h"

#include <algorithm>
#include <cmath>

namespace omnisweep {
namespace {

// Scale from each stored depth to the 0..255 range.
float full_scale_factor(const Image<std::uint8_t>&) { return 1.0f; }
float full_scale_factor(const Image<std::uint16_t>&) { return 255.0f / 65535.0f; }
float full_scale_factor(const Image<float>&) { return 255.0f; }

}  // namespace

int width_of(const AnyImage& image) {
  return std::visit([](const auto& im) { return im.width(); }, image);
}

int height_of(const AnyImage& image) {
  return std::visit([](const auto& im) { return im.height(); }, image);
}

const char* depth_name(const AnyImage& image) {
  constexpr const char* kNames[] = {"8-bit", "16-bit", "float"};
  return kNames[image.index()];
}

FloatImage to_rgb_float255(const AnyImage& image) {
  return std::visit(
      [](const auto& im) {
        FloatImage out(im.width(), im.height(), im.channels());
        const float scale = full_scale_factor(im);
        std::transform(im.pixels().begin(), im.pixels().end(), out.pixels().begin(),
                       [scale](auto v) {
                         const float x = float(v) * scale;
                         return x > 0.0f ? std::min(x, 255.0f) : 0.0f;  // NaN reads as 0
                       });
        return out;
      },
      image);
}

FloatImage reciprocal_or_zero(const FloatImage& image) {
  FloatImage out(image.width(), image.height(), image.channels(), 0.0f);
  for (std::size_t i = 0; i < out.size(); ++i)
    if (image.data()[i] > 0) out.data()[i] = 1.0f / image.data()[i];
  return out;
}

Rgb8Image to_rgb8(const AnyImage& image) {
  if (const auto* u8 = std::get_if<Image<std::uint8_t>>(&image)) return u8->clone();
  const FloatImage f = to_rgb_float255(image);
  Rgb8Image out(f.width(), f.height(), f.channels());
  std::transform(f.pixels().begin(), f.pixels().end(), out.pixels().begin(),
                 [](float v) { return static_cast<std::uint8_t>(std::lround(v)); });
  return out;
}

}  // namespace omnisweep
