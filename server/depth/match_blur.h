// The matching images' blur (DepthOptions::match_blur, --match-blur; docs/accuracy.md): a
// Gaussian of sigma pixels over each camera's matching image before the sweep, the ISB filter's
// guide and the matching features read it; the colour the stitcher samples is not blurred. It
// averages sensor noise before the sweep's bilinear taps (docs/accuracy.md, "Matching blur", has
// what it gains and why it is not in the default). One pass on the GPU
// (shaders/match_blur.comp); match_blur_cpu is the CPU check. Hand-written rather than OpenCV's
// GaussianBlur: the compute core needs Vulkan only, and the check must follow the kernel's float
// order to the bit.
#pragma once

#include <array>
#include <cstdint>

#include "omnisweep/gpu/buffer.h"
#include "omnisweep/gpu/kernel.h"
#include "omnisweep/gpu/sequence.h"
#include "omnisweep/image/image.h"
#include "server/depth/depth_options.h"

namespace omnisweep::depth {

// The normalised weights w[0..radius] (w[|i|] for offset i) of a Gaussian of `sigma` pixels,
// radius = match_blur_radius(sigma), in float as the kernel gets them. Throws std::invalid_argument
// where sigma is not positive or the radius exceeds kMatchBlurMaxRadius (depth_options.h).
struct MatchBlurWeights {
  int radius = 0;
  std::array<float, kMatchBlurMaxRadius + 1> w{};
};
MatchBlurWeights match_blur_weights(double sigma);

// `image` blurred as match_blur.comp does (edge pixels repeated, rounded to 8 bits).
Rgb8Image match_blur_cpu(Rgb8View image, double sigma);

class MatchBlur {
 public:
  // For `images` camera images of width x height, packed RGBA8 one after another.
  MatchBlur(gpu::Context& context, int width, int height, int images, double sigma);

  // Records the blur of `source` into `blurred` (the same size), without a barrier after it.
  void record(gpu::Sequence& seq, const gpu::Buffer& source, gpu::Buffer& blurred) const;

 private:
  int width_, height_, images_;
  MatchBlurWeights weights_;
  gpu::Kernel kernel_;
};

}  // namespace omnisweep::depth
