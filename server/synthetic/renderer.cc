#include "server/synthetic/renderer.h"

#include <cmath>
#include <numbers>

#include "omnisweep/geometry/equirectangular.h"

namespace omnisweep::synthetic {
namespace {

std::uint8_t to_byte(float v) {
  return std::uint8_t(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f));
}

void store(const Scene& scene, const Ray& ray, float pixel_angle, int x, int y,
           RenderedImage* out) {
  Hit hit;
  if (!scene.intersect(ray, &hit)) return;
  const Eigen::Vector3f c = scene.shade(ray, hit, pixel_angle);
  for (int k = 0; k < 3; ++k) out->rgb(x, y, k) = to_byte(c[k]);
  if (!out->radiance.empty())
    for (int k = 0; k < 3; ++k) out->radiance(x, y, k) = c[k];
  out->inverse_distance(x, y) = 1.0f / hit.t;
}

// The unit ray of pixel (u, v) in camera coordinates, when it lies inside the lens circle.
bool lens_ray(const RigCamera& camera, double u, double v, double cos_half_fov,
              Eigen::Vector3d* ray) {
  return camera.model.unproject(Eigen::Vector2d(u, v), ray) && ray->z() >= cos_half_fov;
}

}  // namespace

RenderedImage render_camera(const Scene& scene, const RigCamera& camera,
                            const Rigid3d& world_from_rig, double lens_half_fov,
                            bool keep_radiance) {
  RenderedImage out{Rgb8Image(camera.width, camera.height), FloatImage(camera.width, camera.height),
                    keep_radiance ? RgbFloatImage(camera.width, camera.height) : RgbFloatImage()};
  const Rigid3d world_from_cam = world_from_rig * camera.rig_from_cam;
  const Eigen::Matrix3f rotation = world_from_cam.rotation.toRotationMatrix().cast<float>();
  const Eigen::Vector3f origin = world_from_cam.translation.cast<float>();
  const double cos_half_fov = std::cos(lens_half_fov);
#pragma omp parallel for schedule(dynamic, 8)
  for (int v = 0; v < camera.height; ++v) {
    Eigen::Vector3d prev;
    bool has_prev = lens_ray(camera, -1, v, cos_half_fov, &prev);
    for (int u = 0; u < camera.width; ++u) {
      Eigen::Vector3d ray;
      if (!lens_ray(camera, u, v, cos_half_fov, &ray)) {
        has_prev = false;
        continue;
      }
      // The pixel's angular size, from its neighbour on the row (texture filtering).
      Eigen::Vector3d next;
      const float pixel_angle = has_prev ? float((ray - prev).norm())
                                : lens_ray(camera, u + 1, v, cos_half_fov, &next)
                                    ? float((next - ray).norm())
                                    : 0.01f;
      store(scene, {origin, rotation * ray.cast<float>()}, pixel_angle, u, v, &out);
      prev = ray;
      has_prev = true;
    }
  }
  return out;
}

RenderedImage render_panorama(const Scene& scene, const Rigid3d& world_from_rig,
                              const Eigen::Vector3d& viewpoint_in_rig, int width, int height) {
  RenderedImage out{Rgb8Image(width, height), FloatImage(width, height)};
  const Eigen::Matrix3f rotation = world_from_rig.rotation.toRotationMatrix().cast<float>();
  const Eigen::Vector3f origin = (world_from_rig * viewpoint_in_rig).cast<float>();
  const float pixel_angle = std::numbers::pi_v<float> / float(height);
#pragma omp parallel for schedule(dynamic, 8)
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const Eigen::Vector3f dir = equirect_direction<float>(float(x), float(y), width, height);
      store(scene, {origin, (rotation * dir).normalized()}, pixel_angle, x, y, &out);
    }
  }
  return out;
}

Gray8Image lens_mask(const RigCamera& camera, double lens_half_fov) {
  Gray8Image mask(camera.width, camera.height);
  const double cos_half_fov = std::cos(lens_half_fov);
  for (int v = 0; v < camera.height; ++v) {
    for (int u = 0; u < camera.width; ++u) {
      Eigen::Vector3d ray;
      if (lens_ray(camera, u, v, cos_half_fov, &ray)) mask(u, v) = 255;
    }
  }
  return mask;
}

}  // namespace omnisweep::synthetic
