#include "server/stitch/same_size.h"

#include <stdexcept>
#include <string>

namespace omnisweep::stitch {
namespace {

std::string size_text(const SizedImage& image) {
  return std::to_string(image.width) + "x" + std::to_string(image.height);
}

}  // namespace

void require_same_size(std::string_view pass, std::initializer_list<SizedImage> images) {
  if (images.size() == 0) return;
  const SizedImage& first = *images.begin();
  for (const SizedImage& image : images) {
    if (image.width != first.width || image.height != first.height) {
      throw std::invalid_argument(std::string(pass) + ": the " + std::string(image.name) + " is " +
                                  size_text(image) + ", the " + std::string(first.name) + " " +
                                  size_text(first));
    }
  }
}

}  // namespace omnisweep::stitch
