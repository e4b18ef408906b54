// A sparsification curve as a picture (docs/accuracy.md): MAE of the pixels kept against the
// share removed, by confidence and by the oracle, with AUSE and the MAE at 80 % in the legend.
#pragma once

#include <string>

#include "omnisweep/image/image.h"
#include "server/stitch/panorama_metrics.h"

namespace omnisweep::tools {

// A width x height RGB plot; `title` goes above the axes.
Rgb8Image plot_sparsification(const stitch::Sparsification& curve, const std::string& title,
                              int width = 640, int height = 420);

}  // namespace omnisweep::tools
