// The size check every panorama pass's CPU reference and every metric makes of its inputs: one
// message that names the pass and the image that differs, with both sizes.
#pragma once

#include <initializer_list>
#include <string_view>

namespace omnisweep::stitch {

struct SizedImage {
  std::string_view name;  // what the message calls it: "colour", "confidence", "ground truth"
  int width = 0;
  int height = 0;
};

template <typename Image>
SizedImage sized(std::string_view name, const Image& image) {
  return {name, image.width(), image.height()};
}

// Throws std::invalid_argument ("<pass>: the <name> is WxH, the <first name> WxH") at the first
// image whose size is not the first one's.
void require_same_size(std::string_view pass, std::initializer_list<SizedImage> images);

}  // namespace omnisweep::stitch
