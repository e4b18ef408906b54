// Brings frames to the depth estimator (the file edge: OpenCV resizing): images as 8-bit RGB,
// at the matching resolution by area interpolation (rounded), and masks thresholded as
// ALGORITHM.md §2 prescribes.
#pragma once

#include <optional>
#include <vector>

#include "omnisweep/dataset/dataset.h"
#include "server/depth/depth_options.h"

namespace omnisweep::depth {

// Every camera image of a frame as 8-bit RGB at its stored resolution (colour for stitching).
std::vector<Rgb8Image> rgb8_images(const Frame& frame);
// The same images at the matching resolution.
std::vector<Rgb8Image> matching_images(const std::vector<Rgb8Image>& images,
                                       const DepthOptions& options);
// Masks (at any resolution; nullopt = all usable) as usable masks at the matching resolution.
std::vector<std::optional<Gray8Image>> matching_masks(
    const std::vector<std::optional<Gray8Image>>& masks, const DepthOptions& options);

// The reference cameras' images (taken from `images`, which keeps the others) at their size in
// `color_rig`, resized by area where they differ: what the stitcher samples colour from.
std::vector<Rgb8Image> reference_color_images(std::vector<Rgb8Image>& images, const Rig& color_rig,
                                              const std::vector<int>& references);

}  // namespace omnisweep::depth
