// Brings dataset frames to the depth estimator (the file edge: OpenCV resizing): images as
// 8-bit RGB at the matching resolution (area interpolation, rounded), masks thresholded as
// ALGORITHM.md §2 prescribes.
#pragma once

#include <optional>
#include <vector>

#include "omnisweep/dataset/dataset.h"
#include "server/depth/depth_options.h"

namespace omnisweep::depth {

std::vector<Rgb8Image> matching_images(const Frame& frame, const DepthOptions& options);
std::vector<std::optional<Gray8Image>> matching_masks(const Dataset& dataset,
                                                      const DepthOptions& options);
std::vector<const Rgb8Image*> pointers(const std::vector<Rgb8Image>& images);

}  // namespace omnisweep::depth
