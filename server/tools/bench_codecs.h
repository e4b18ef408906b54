// omnisweep-bench's codec section (bench_codecs.cc).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "omnisweep/gpu/context.h"
#include "omnisweep/image/image.h"
#include "omnisweep/rig/rig.h"
#include "server/stitch/stitcher.h"

namespace omnisweep::tools {

// Estimates 2048x1024 panoramas (the synthetic rig, and the kaist-rig frame when kaist_dir holds
// it) and compresses them: the distance codec at the defaults side by side with 16-bit PNG at
// level 1 (what ROS 2's compressedDepth stores), runs interleaved so both see the same machine
// load, then the light setting and JPEG. Wall and CPU ms, sizes, quantisation error, and the
// ratios against PNG.
void codec_section(gpu::Context& context, const std::string& kaist_dir, bool json);

// An estimated 2048x1024 panorama (depth and stitching at their defaults) of a frame: what the
// server compresses.
stitch::Panorama estimate_panorama(gpu::Context& context, const Rig& rig,
                                   const std::vector<Rgb8Image>& images,
                                   const std::vector<std::optional<Gray8Image>>& masks_full);
// The synthetic rig's first frame, estimated so.
stitch::Panorama synthetic_panorama(gpu::Context& context);

}  // namespace omnisweep::tools
