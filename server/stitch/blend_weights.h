// Blending weights of distance-aware stitching (ALGORITHM.md §5 step 3) in plain C++; the
// Stitcher computes them on the GPU and the tests compare the two. Once per calibration:
// per panorama pixel and reference camera, how well that camera sees the direction (little
// parallax, inside its usable mask), normalised over the references, smoothed with a 31x31 box
// that wraps around the panorama horizontally, and normalised again.
#pragma once

#include <optional>
#include <vector>

#include "omnisweep/image/image.h"
#include "omnisweep/rig/rig.h"

namespace omnisweep::stitch {

struct BlendSetup {
  const Rig* rig = nullptr;  // at the matching resolution
  std::vector<int> references;
  Eigen::Vector3d viewpoint_in_rig = Eigen::Vector3d::Zero();
  std::vector<std::optional<Gray8Image>>
      usable;  // per camera, matching resolution; empty = all usable
  double min_distance = 0.55;
  double max_distance = 100.0;
  int panorama_width = 2048;
  int panorama_height = 1024;
};

// One weight image per reference (panorama size); they sum to 1 at every pixel.
std::vector<FloatImage> blend_weights(const BlendSetup& setup);

// A w x h box filter (w, h odd) on a 1-channel image; horizontally wrapping or padded with
// `border` outside the image. Exposed for its test.
FloatImage box_filter(const FloatImage& image, int size, bool wrap_x, float border);

}  // namespace omnisweep::stitch
