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
//
// A warper can also hold several warps of the same sizes ("layers", the stitcher's references):
// each dispatch then covers every layer (z = layer), the source maps lie layer after layer in
// one buffer and so do the results.
#pragma once

#include <optional>
#include <stdexcept>
#include <string_view>
#include <vector>

#include "omnisweep/gpu/kernel.h"
#include "omnisweep/gpu/sequence.h"
#include "omnisweep/image/image.h"
#include "omnisweep/options/option_error.h"
#include "omnisweep/reproject/gpu_camera.h"

namespace omnisweep::reproject {

// The options' check()s throw omnisweep::option_error (omnisweep/options/option_error.h).
using omnisweep::option_error;
// The distance range and inpainting passes, which WarpOptions and the options that make one
// (StitchOptions) share; throws option_error naming `owner`.
void check_warp_range(std::string_view owner, double min_distance, double max_distance,
                      int inpaint_passes);

struct WarpOptions {
  double min_distance = 0.55;  // d_min and d_max of the background direction (ALGORITHM.md §5)
  double max_distance = 100.0;
  int inpaint_passes = 32;  // more than the widest expected hole
  // 1: each source pixel lands on its nearest target pixel (the paper). Larger: it covers its
  // footprint in the target, up to this many pixels across (views that magnify the source).
  double max_splat = 1.0;
  // Allocate what record_color needs.
  bool color = false;
  // record_color: a point is hidden from the source when the source's distance map holds a
  // value nearer than (1 - occlusion_tolerance) times the point's distance.
  double occlusion_tolerance = 0.1;
  // Throws std::invalid_argument naming the field, its value and what is allowed.
  void check() const;
};

// One warp of a layered ForwardWarper.
struct WarpLayer {
  GpuCamera source;
  GpuCamera target;
};

class ForwardWarper {
 public:
  // `source.rows` must be the identity; `target.rows` hold target_from_source. The background
  // directions are computed by the first record(), and again after set_target().
  ForwardWarper(gpu::Context& context, const GpuCamera& source, const GpuCamera& target,
                const WarpOptions& options);
  // Several layers, all sources of one size and all targets of one size; not with
  // WarpOptions::color.
  ForwardWarper(gpu::Context& context, std::vector<WarpLayer> layers, const WarpOptions& options);

  // A new target camera or pose of the same size (a moving viewer), for a warper of one layer.
  // Not while a sequence that uses this warper is still running.
  void set_target(const GpuCamera& target);
  int layers() const { return int(layers_.size()); }
  void set_inpaint_passes(int passes);

  // Records: clear the z-buffer, warp `distance` (source width x height floats per layer, layer
  // after layer; <= 0 = none), inpaint. The result is valid after the sequence has run.
  void record(gpu::Sequence& seq, const gpu::Buffer& distance);
  // Records, after record(): the colour of every target pixel sampled from `source_color`
  // (source pixels packed as pack_rgba8 makes them) where the source sees that point, then the
  // rest (disocclusions) inpainted from the background side. `distance` is the map given to
  // record(). Needs WarpOptions::color.
  void record_color(gpu::Sequence& seq, const gpu::Buffer& distance,
                    const gpu::Buffer& source_color);

  // Adaptive inpainting (novel views, where hole widths vary with the pose): record_warp, then
  // inpaint_until_filled runs passes in batches of `batch`, submitting `seq` (with what was
  // recorded before) after each batch, until a pass fills nothing (the fixed point) or
  // `max_passes` ran. Returns the passes run; adds the GPU milliseconds to *gpu_ms. The same for
  // colour: record_color_sample, then inpaint_color_until_filled.
  void record_warp(gpu::Sequence& seq, const gpu::Buffer& distance);
  int inpaint_until_filled(gpu::Sequence& seq, int max_passes, int batch, double* gpu_ms);
  void record_color_sample(gpu::Sequence& seq, const gpu::Buffer& distance,
                           const gpu::Buffer& source_color);
  int inpaint_color_until_filled(gpu::Sequence& seq, int max_passes, int batch, double* gpu_ms);

  // Target width x height per layer; bits of float distances, 0xffffffff where there is none.
  const gpu::Buffer& result() const;
  // The packed RGBA8 colour of layer 0 (WarpOptions::color), after the last record.
  const gpu::Buffer& color_result() const;
  // The result of `layer` as distances, 0 where there is none.
  FloatImage download(int layer = 0) const;
  // The colour after record_color, black where nothing could be filled.
  Rgb8Image download_color() const;

  // Per target pixel, its two background-side neighbours and their weights (struct Direction in
  // shaders/include/inpaint.glsl), as the last record computed them: for checks of inpainting.
  const gpu::Buffer& directions() const { return directions_; }

  int target_width() const { return int(target().width); }
  int target_height() const { return int(target().height); }
  const GpuCamera& target() const { return layers_[0].target; }

 private:
  // Records passes [first_pass, first_pass + passes), kPassesPerDispatch to a dispatch, from
  // buffers[*current] on; *current ends on the buffer that holds the result.
  void record_inpaint(gpu::Sequence& seq, const gpu::Kernel& kernel, gpu::Buffer* buffers,
                      int first_pass, int passes, int* current) const;
  int run_until_filled(gpu::Sequence& seq, const gpu::Kernel& kernel, gpu::Buffer* buffers,
                       int max_passes, int batch, double* gpu_ms, int* current);

  const GpuCamera& source() const { return layers_[0].source; }
  void upload_cameras();

  gpu::Context* context_;
  std::vector<WarpLayer> layers_;
  WarpOptions options_;
  bool directions_stale_ = true;
  gpu::Buffer cameras_;
  gpu::Buffer directions_;
  gpu::Buffer buffers_[2];   // ping-pong z-buffers
  gpu::Buffer filled_;       // per pass: did it fill anything
  int result_ = 0;           // which of buffers_ holds the distance result
  int color_result_ = 0;     // which of color_buffers_ holds the colour result
  std::uint32_t tile_ = 32;  // inpainting tile side (inpaint_tile.glsl), to fit shared memory
  gpu::Buffer tile_status_;  // per tile and layer, twice: one dispatch writes what the next reads
  std::vector<gpu::Buffer> color_buffers_;  // ping-pong colours (WarpOptions::color only)
  // warp_, directions_kernel_ and sample_color_ are compiled for the source's and the target's
  // camera models (model_constants), and again when set_target changes the target's model.
  gpu::Kernel warp_;
  gpu::Kernel directions_kernel_;
  gpu::Kernel inpaint_;
  std::optional<gpu::Kernel> sample_color_;
  std::optional<gpu::Kernel> inpaint_color_;
};

}  // namespace omnisweep::reproject
