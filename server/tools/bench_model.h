// omnisweep-bench --sections model: the frame cost model (bench_model.cc).
#pragma once

#include "omnisweep/gpu/context.h"
#include "server/depth/depth_options.h"

namespace omnisweep::tools {

// Runs frames of the depth estimator (with `options`) and the stitcher at their defaults (or with
// matching `resolution` and a panorama of 2 x `resolution` x `resolution`), records what they
// submit (gpu::CommandLog) and prints, per stage and for the frame, dispatches, barriers, host
// round trips, bound bytes and the predicted time on named devices.
void model_section(gpu::Context& context, depth::DepthOptions options, int resolution, bool json);

}  // namespace omnisweep::tools
