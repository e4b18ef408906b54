// Reprojection of a distance map to another viewpoint on the GPU: forward warp with a z-buffer
// (the nearest surface always wins) and directional inpainting of disocclusions from the
// background side (paper §3.3, ALGORITHM.md §5 steps 1-2). The server stitches panoramas with
// it; the client SDK renders novel views with it.
//
//   source: the camera the distance map was estimated in (any model), at its pixel grid;
//   target: any camera model or an equirectangular panorama (pack_equirectangular), with
//           target_from_source taking points from the source's frame to the target's.
//   Distances are Euclidean, from each camera's centre, in metres.
//
//   ForwardWarper warper(context, source, target, {.min_distance = 0.55, .max_distance = 100});
//   seq.begin(); warper.record(seq, distance_buffer); seq.submit_and_wait();
//   FloatImage at_target = warper.download();  // 0 where nothing landed (after inpainting)
#pragma once

#include "omnisweep/gpu/kernel.h"
#include "omnisweep/gpu/sequence.h"
#include "omnisweep/image/image.h"
#include "omnisweep/reproject/gpu_camera.h"

namespace omnisweep::reproject {

struct WarpOptions {
  double min_distance = 0.55;  // d_min and d_max of the background direction (ALGORITHM.md §5)
  double max_distance = 100.0;
  int inpaint_passes = 32;  // more than the widest expected hole
};

class ForwardWarper {
 public:
  // `source.rows` must be the identity; `target.rows` hold target_from_source. The background
  // directions are computed here, once per pose.
  ForwardWarper(gpu::Context& context, const GpuCamera& source, const GpuCamera& target,
                const WarpOptions& options);

  // Records: clear the z-buffer, warp `distance` (source width x height floats; <= 0 = none),
  // inpaint. The result is valid after the sequence has run.
  void record(gpu::Sequence& seq, const gpu::Buffer& distance);

  // Target width x height; bits of float distances, 0xffffffff where there is none.
  const gpu::Buffer& result() const;
  // The result as distances, 0 where there is none.
  FloatImage download() const;

  int target_width() const { return int(target_.width); }
  int target_height() const { return int(target_.height); }

 private:
  GpuCamera source_;
  GpuCamera target_;
  WarpOptions options_;
  gpu::Buffer cameras_;
  gpu::Buffer directions_;
  gpu::Buffer buffers_[2];  // ping-pong z-buffers
  gpu::Kernel warp_;
  gpu::Kernel inpaint_;
};

}  // namespace omnisweep::reproject
