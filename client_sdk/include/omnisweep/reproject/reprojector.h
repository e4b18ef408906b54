// Novel views of an RGB-D panorama on the GPU: what teleoperation and VR apps render from a
// received frame. The same forward warp, z-buffer and directional inpainting as the server's
// stitcher (forward_warp.h) carry the distance to the requested pose; colour is then sampled
// from the panorama where it sees the point, and disocclusions fill from the background side.
//
//   Reprojector reprojector(context);
//   reprojector.set_panorama(frame.color, frame.distance, frame.viewpoint);
//   Rigid3d rig_from_eye(Eigen::Quaterniond::Identity(), {0.03, 0, 0});
//   View eye = reprojector.render_pinhole(rig_from_eye, pinhole_for_fov(1024, 1024, 90), 1024,
//   1024);
//
// Poses are rig_from_view (position and orientation of the view in the rig frame). Views look
// along their +z axis with x right and y down, as the rig's cameras; an equirectangular view
// uses the ALGORITHM.md §5 convention in the view's axes. Distances are Euclidean, in metres,
// from the view's centre; 0 where nothing could be filled.

//
// This header and gpu/context.h are what an app includes: they need the Vulkan C headers only
// (VkBuffer in ViewBuffers), not Vulkan-Hpp, so the app keeps its own include order and NDEBUG.
#pragma once

#include <vulkan/vulkan_core.h>

#include <Eigen/Geometry>
#include <array>
#include <memory>

#include "omnisweep/camera/pinhole_camera.h"
#include "omnisweep/geometry/rigid3.h"
#include "omnisweep/gpu/context.h"
#include "omnisweep/image/image.h"

namespace omnisweep::reproject {

struct ReprojectorOptions {
  double min_distance = 0.55;  // the stream's distance range (StreamDescription)
  double max_distance = 100.0;
  double max_splat = 4.0;  // footprint splatting for views that magnify the panorama
  double occlusion_tolerance = 0.1;
  // Inpainting runs until a pass fills nothing, at most the widest hole the pose can open (its
  // translation times the inverse distance of the panorama's nearest surface, in target
  // pixels) plus 4 for cracks, and at most this many passes.
  int max_inpaint_passes = 256;
  // With a confidence (set_panorama's): pixels less confident than this are treated as holes and
  // inpainted from their surroundings, as pixels with no value are. 0: every pixel is used.
  double min_confidence = 0.0;

  void check() const;  // throws std::invalid_argument naming the bad option
};

struct View {
  Rgb8Image color;
  FloatImage distance;     // metres from the view's centre, 0 = none
  int inpaint_passes = 0;  // distance inpainting passes run for this pose
};

// Buffers of the context's device (an app's own, with gpu::ExternalVulkan) that the *_into
// renders fill without a round trip through the host: `color` width x height uint32 texels,
// RGBA8 with R in the low byte (A = 255 where colour was filled), `distance` width x height
// float32 metres from the view's centre (NaN, all bits set, where nothing could be filled).
// Each needs VK_BUFFER_USAGE_TRANSFER_DST_BIT and at least 4 * width * height bytes from
// `offset`; either may be VK_NULL_HANDLE. When the call returns the copies have completed.
struct ViewBuffers {
  VkBuffer color = VK_NULL_HANDLE;
  VkDeviceSize color_offset = 0;
  VkBuffer distance = VK_NULL_HANDLE;
  VkDeviceSize distance_offset = 0;
};

// The six faces of a cube map, in this order; each is a 90-degree pinhole view.
enum class CubeFace { kRight, kLeft, kDown, kUp, kFront, kBack };
// view_from_face: the rotation of a face's camera within the view (x right, y down, z forward:
// front looks along +z; down and up faces have the front at the top and bottom of the image).
Eigen::Quaterniond cube_face_rotation(CubeFace face);

// A pinhole camera of width x height pixels with the given horizontal field of view, square
// pixels and the principal point at the image centre. Throws std::invalid_argument.
PinholeCamera<double> pinhole_for_fov(int width, int height, double horizontal_fov_deg);

class Reprojector {
 public:
  explicit Reprojector(gpu::Context& context, const ReprojectorOptions& options = {});
  ~Reprojector();
  Reprojector(Reprojector&&) noexcept;
  Reprojector& operator=(Reprojector&&) noexcept;

  // The panorama to render from: colour (RGB) and distance (metres, 0 = none) of the same
  // width x height, in the rig frame's axes, centred on `viewpoint` (rig frame).
  void set_panorama(Rgb8View color, FloatView distance, const Eigen::Vector3d& viewpoint);
  // The same with the distance's confidence in [0, 1] (RgbdFrame::confidence; empty: none), for
  // ReprojectorOptions::min_confidence.
  void set_panorama(Rgb8View color, FloatView distance, const Eigen::Vector3d& viewpoint,
                    FloatView confidence);

  View render_panorama(const Rigid3d& rig_from_view, int width, int height);
  View render_pinhole(const Rigid3d& rig_from_view, const PinholeCamera<double>& camera, int width,
                      int height);
  std::array<View, 6> render_cube_map(const Rigid3d& rig_from_view, int face_size);
  // The same views written into the app's buffers (ViewBuffers); return the inpainting passes.
  int render_panorama_into(const Rigid3d& rig_from_view, int width, int height,
                           const ViewBuffers& out);
  int render_pinhole_into(const Rigid3d& rig_from_view, const PinholeCamera<double>& camera,
                          int width, int height, const ViewBuffers& out);

  // GPU milliseconds of the last render (0 where the device has no timestamps).
  double last_gpu_ms() const;

 private:
  struct State;  // the panorama on the GPU, the warpers and the command buffer (reprojector.cc)
  std::unique_ptr<State> state_;
};

}  // namespace omnisweep::reproject
