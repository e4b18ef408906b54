#include "server/depth/match_blur.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace omnisweep::depth {

namespace {

constexpr std::uint32_t kTile = 16;  // match_blur.comp's tile

struct BlurPush {
  std::uint32_t width, height, images, radius;
  std::array<float, kMatchBlurMaxRadius + 1> weights;
};

}  // namespace

MatchBlurWeights match_blur_weights(double sigma) {
  if (!(sigma > 0) || !std::isfinite(sigma))
    throw std::invalid_argument("match-blur: sigma must be a positive number of pixels");
  MatchBlurWeights out;
  out.radius = match_blur_radius(sigma);
  if (out.radius > kMatchBlurMaxRadius) {
    throw std::invalid_argument("match-blur: sigma " + std::to_string(sigma) +
                                " pixels at the matching resolution reaches " +
                                std::to_string(out.radius) + " pixels, at most " +
                                std::to_string(kMatchBlurMaxRadius) + " are supported");
  }
  double sum = 0;
  std::array<double, kMatchBlurMaxRadius + 1> w{};
  for (int i = 0; i <= out.radius; ++i) {
    w[std::size_t(i)] = std::exp(-0.5 * i * i / (sigma * sigma));
    sum += (i == 0 ? 1.0 : 2.0) * w[std::size_t(i)];
  }
  for (int i = 0; i <= out.radius; ++i) out.w[std::size_t(i)] = float(w[std::size_t(i)] / sum);
  return out;
}

Rgb8Image match_blur_cpu(Rgb8View image, double sigma) {
  const MatchBlurWeights weights = match_blur_weights(sigma);
  const int r = weights.radius, width = image.width(), height = image.height();
  auto weight = [&](int i) { return weights.w[std::size_t(std::abs(i))]; };
  // Rows first, kept in float, then columns: the kernel's order.
  std::vector<float> rows(std::size_t(width) * height * 3);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      for (int c = 0; c < 3; ++c) {
        float sum = 0.0f;
        for (int i = -r; i <= r; ++i)
          sum += weight(i) * float(image(std::clamp(x + i, 0, width - 1), y, c));
        rows[(std::size_t(y) * width + x) * 3 + c] = sum;
      }
    }
  }
  Rgb8Image out(width, height);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      for (int c = 0; c < 3; ++c) {
        float sum = 0.0f;
        for (int i = -r; i <= r; ++i)
          sum +=
              weight(i) * rows[(std::size_t(std::clamp(y + i, 0, height - 1)) * width + x) * 3 + c];
        out(x, y, c) = std::uint8_t(std::clamp(std::floor(sum + 0.5f), 0.0f, 255.0f));
      }
    }
  }
  return out;
}

MatchBlur::MatchBlur(gpu::Context& context, int width, int height, int images, double sigma)
    : width_(width),
      height_(height),
      images_(images),
      weights_(match_blur_weights(sigma)),
      kernel_(context, gpu::Shader::kMatchBlur,
              {.bindings = {1, 1},
               .push_constant_bytes = sizeof(BlurPush),
               .local_size = {kTile, kTile, 1},
               .constants = {}}) {
  if (width < 1 || height < 1 || images < 1)
    throw std::invalid_argument("match-blur: no images to blur");
}

void MatchBlur::record(gpu::Sequence& seq, const gpu::Buffer& source, gpu::Buffer& blurred) const {
  const BlurPush push{std::uint32_t(width_), std::uint32_t(height_), std::uint32_t(images_),
                      std::uint32_t(weights_.radius), weights_.w};
  seq.dispatch(kernel_, {source, blurred}, push,
               kernel_.groups_for(width_, height_, std::uint32_t(images_)));
}

}  // namespace omnisweep::depth
