// omnisweep-bench --sections model: the frame cost model (bench_model.cc).
#pragma once

#include "omnisweep/gpu/context.h"

namespace omnisweep::tools {

// Runs frames of the depth estimator and the stitcher at their defaults (or with matching
// `resolution` and a panorama of 2 x `resolution` x `resolution`), records what they submit
// (gpu::CommandLog) and prints, per stage and for the frame, dispatches, barriers, host round
// trips, bound bytes and the predicted time on named devices.
void model_section(gpu::Context& context, int resolution, bool json);

}  // namespace omnisweep::tools
