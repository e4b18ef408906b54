// omnisweep-bench --sections accuracy: the method's variants side by side, in the style of the
// paper's Table 3 (bench_accuracy.cc).
#pragma once

#include <string>

#include "omnisweep/gpu/context.h"

namespace omnisweep::tools {

struct AccuracySectionOptions {
  int frames = 2;       // synthetic frames per set
  int resolution = 0;   // matching resolution (panorama 2R x R); 0: the defaults
  std::string dev_set;  // a dataset with ground truth (blender-hall); empty: none
};

// Every variant (the paper's cost, the robust costs, with and without the photometric
// correction) on the synthetic rig's frames without and with realistic lenses, each without and
// with a sensor noise of one level, and on the development set: MAE, RMSE, > 0.1, > 0.4, colour
// PSNR and SSIM, ms per frame here, and the frame's predicted ms on a Jetson AGX Xavier from the
// cost model.
void accuracy_section(gpu::Context& context, const AccuracySectionOptions& options, bool json);

}  // namespace omnisweep::tools
