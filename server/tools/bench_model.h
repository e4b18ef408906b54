// omnisweep-bench --sections model: the frame cost model (bench_model.cc).
#pragma once

#include "omnisweep/gpu/command_log.h"
#include "omnisweep/gpu/context.h"
#include "server/depth/depth_options.h"

namespace omnisweep::tools {

// The frame's predicted time on the Jetson AGX Xavier (the paper's device) from a log of it.
double predicted_xavier_ms(const gpu::CommandLog& log);

// Runs frames of the depth estimator (with `options`) and the stitcher at their defaults (with
// the plane fill `plane_fill`, the region planes if `region_planes`, the edge check if
// `edge_check` and the membrane fill if `membrane_fill`, as StitchOptions; the membrane fill's
// solve is one workgroup's serial work, which the model's bytes and dispatches do not count), or
// with matching `resolution` and a panorama of 2 x `resolution` x `resolution`; records what they
// submit (gpu::CommandLog) and prints, per stage and for the frame, dispatches, barriers, host
// round trips, bound bytes and the predicted time on named devices; where the variants are not
// the paper's method, the paper's frame recorded beside it and the ratio of the two per device.
void model_section(gpu::Context& context, depth::DepthOptions options, double plane_fill,
                   bool region_planes, bool edge_check, bool membrane_fill, int resolution,
                   bool json);

}  // namespace omnisweep::tools
