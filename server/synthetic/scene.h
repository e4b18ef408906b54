// Procedural scenes for the synthetic rig: an enclosed hall (textured walls with large plain
// areas, tiled floor, plain ceiling) holding boxes, spheres and thin poles, all analytic.
// World frame: metres, y down (like the cameras), the floor at y = room.max.y.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "server/synthetic/procedural_texture.h"

namespace omnisweep::synthetic {

struct Ray {
  Eigen::Vector3f origin;
  Eigen::Vector3f direction;  // unit length
};

struct Hit {
  float t = 0.0f;                                    // distance along the ray, metres
  Eigen::Vector3f normal = Eigen::Vector3f::Zero();  // unit, facing the ray
  int material = 0;
};

struct Box {  // rotated by `yaw` about the vertical (y) axis
  Eigen::Vector3f center;
  Eigen::Vector3f half_size;
  float yaw = 0.0f;
  int material = 0;
};

struct Sphere {
  Eigen::Vector3f center;
  float radius = 0.0f;
  int material = 0;
};

struct Pole {  // vertical cylinder from the floor to the ceiling
  float x = 0.0f, z = 0.0f, radius = 0.0f;
  int material = 0;
};

struct Room {  // the inside of an axis-aligned box
  Eigen::Vector3f min, max;
  int wall_material = 0, floor_material = 0, ceiling_material = 0;
};

class Scene {
 public:
  // A hall generated from `seed`. Nothing comes nearer than `clearance` metres (horizontally)
  // to any point of `keep_clear` (the rig's path), except one deliberate near sphere whose
  // surface lies `near_distance` from keep_clear[0] and at least that far from the whole path.
  static Scene hall(std::uint64_t seed, const std::vector<Eigen::Vector3f>& keep_clear,
                    float clearance = 0.8f, float near_distance = 0.65f);

  // Nearest intersection with t > 1e-4; false only for rays leaving the room (never from inside).
  bool intersect(const Ray& ray, Hit* hit) const;
  // View-independent shaded colour (linear [0, 1]) of the surface hit by `ray`, for a pixel
  // that subtends `pixel_angle` radians.
  Eigen::Vector3f shade(const Ray& ray, const Hit& hit, float pixel_angle) const;

  const Room& room() const { return room_; }
  const std::vector<Box>& boxes() const { return boxes_; }
  const std::vector<Sphere>& spheres() const { return spheres_; }
  const std::vector<Pole>& poles() const { return poles_; }
  const std::vector<Material>& materials() const { return materials_; }

 private:
  Room room_;
  std::vector<Box> boxes_;
  std::vector<Sphere> spheres_;
  std::vector<Pole> poles_;
  std::vector<Material> materials_;
  Eigen::Vector3f light_;  // a point light below the ceiling
};

}  // namespace omnisweep::synthetic
