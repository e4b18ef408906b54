#include "server/depth/depth_inputs.h"

#include "omnisweep/image/image_io.h"

namespace omnisweep::depth {

std::vector<Rgb8Image> rgb8_images(const Frame& frame) {
  std::vector<Rgb8Image> out;
  for (const AnyImage& image : frame.images) out.push_back(to_rgb8(image));
  return out;
}

std::vector<Rgb8Image> matching_images(const std::vector<Rgb8Image>& images,
                                       const DepthOptions& options) {
  std::vector<Rgb8Image> out;
  for (const Rgb8Image& rgb : images) {
    out.push_back(rgb.width() == options.matching_width && rgb.height() == options.matching_height
                      ? rgb.clone()
                      : resize_area(rgb, options.matching_width, options.matching_height));
  }
  return out;
}

std::vector<std::optional<Gray8Image>> matching_masks(
    const std::vector<std::optional<Gray8Image>>& masks, const DepthOptions& options) {
  std::vector<std::optional<Gray8Image>> out;
  for (const auto& mask : masks) {
    if (mask) {
      out.emplace_back(usable_mask(*mask, options.matching_width, options.matching_height));
    } else {
      out.emplace_back(std::nullopt);
    }
  }
  return out;
}

std::vector<Rgb8Image> reference_color_images(std::vector<Rgb8Image>& images, const Rig& color_rig,
                                              const std::vector<int>& references) {
  std::vector<Rgb8Image> out;
  for (int r : references) {
    const RigCamera& cam = color_rig.cameras[r];
    Rgb8Image rgb = std::move(images[r]);
    if (rgb.width() != cam.width || rgb.height() != cam.height)
      rgb = resize_area(rgb, cam.width, cam.height);
    out.push_back(std::move(rgb));
  }
  return out;
}

}  // namespace omnisweep::depth
