// Renders a Scene through any rig camera (fisheye images with per-pixel inverse distance) and
// as an equirectangular panorama (ALGORITHM.md §5 convention), one ray per pixel centre.
#pragma once

#include <Eigen/Core>

#include "omnisweep/geometry/rigid3.h"
#include "omnisweep/image/image.h"
#include "omnisweep/rig/rig.h"
#include "server/synthetic/scene.h"

namespace omnisweep::synthetic {

struct RenderedImage {
  Rgb8Image rgb;  // RGB, black outside the lens circle
  FloatImage
      inverse_distance;  // 1 / Euclidean distance (m^-1) from the projection centre; 0 where no ray
  // render_camera with keep_radiance only (else empty): the shaded colour in [0, 1] that `rgb`
  // rounds, for the sensor model (photometric.h), which rounds once, after its gain, vignetting and
  // noise.
  RgbFloatImage radiance{};
};

// Pixels whose ray is more than `lens_half_fov` radians off the optical axis see no light
// (outside the lens' image circle), as on a real fisheye sensor.
// `keep_radiance`: also fill RenderedImage::radiance (12 bytes a pixel), for the sensor model.
RenderedImage render_camera(const Scene& scene, const RigCamera& camera,
                            const Rigid3d& world_from_rig, double lens_half_fov,
                            bool keep_radiance = false);

// Panorama of width x height seen from `viewpoint_in_rig`, axes aligned with the rig frame.
RenderedImage render_panorama(const Scene& scene, const Rigid3d& world_from_rig,
                              const Eigen::Vector3d& viewpoint_in_rig, int width, int height);

// 255 where a pixel's ray lies within lens_half_fov of the optical axis, else 0.
Gray8Image lens_mask(const RigCamera& camera, double lens_half_fov);

}  // namespace omnisweep::synthetic
