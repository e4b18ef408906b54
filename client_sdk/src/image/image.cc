#include "omnisweep/image/image.h"

#include <algorithm>
#include <cmath>

namespace omnisweep {
namespace {

// Scale from each stored depth to the 0..255 range.
float full_scale_factor(const Rgb8Image&) { return 1.0f; }
float full_scale_factor(const Rgb16Image&) { return 255.0f / 65535.0f; }
float full_scale_factor(const RgbFloatImage&) { return 255.0f; }

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

RgbFloatImage to_rgb_float255(const AnyImage& image) {
  return std::visit(
      [](const auto& im) {
        RgbFloatImage out(im.width(), im.height());
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

FloatImage reciprocal_or_zero(FloatView image) {
  FloatImage out(image.width(), image.height());
  for (std::size_t i = 0; i < out.size(); ++i)
    if (image.data()[i] > 0) out.data()[i] = 1.0f / image.data()[i];
  return out;
}

Rgb8Image to_rgb8(const AnyImage& image) {
  if (const auto* u8 = std::get_if<Rgb8Image>(&image)) return u8->clone();
  const RgbFloatImage f = to_rgb_float255(image);
  Rgb8Image out(f.width(), f.height());
  std::transform(f.pixels().begin(), f.pixels().end(), out.pixels().begin(),
                 [](float v) { return static_cast<std::uint8_t>(std::lround(v)); });
  return out;
}

}  // namespace omnisweep
