// omnisweep-bench's reprojection section (bench_reproject.cc).
#pragma once

#include "omnisweep/gpu/context.h"

namespace omnisweep::tools {

// Times Reprojector on a 2048x1024 synthetic panorama: to a 1024x1024 pinhole view and to a
// 2048x1024 panorama, 5 cm and 20 cm from the viewpoint; GPU ms and wall ms (with the upload
// and download), medians of `iterations` runs.
void reproject_section(gpu::Context& context, int iterations, bool json);

}  // namespace omnisweep::tools
