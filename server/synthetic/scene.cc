#include "server/synthetic/scene.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace omnisweep::synthetic {
namespace {

constexpr float kEpsilon = 1e-4f;

// splitmix64: a fixed, portable generator (std distributions differ between libraries).
class Random {
 public:
  explicit Random(std::uint64_t seed) : state_(seed) {}
  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  float uniform(float lo, float hi) {
    return lo + (hi - lo) * float(next() >> 40) / float(1 << 24);
  }
  int index(int n) { return int(next() % std::uint64_t(n)); }
  // A point drawn uniformly in the box [lo, hi], z first, then y, then x.
  Eigen::Vector3f uniform_zyx(const Eigen::Vector3f& lo, const Eigen::Vector3f& hi) {
    const float z = uniform(lo.z(), hi.z()), y = uniform(lo.y(), hi.y());
    return {uniform(lo.x(), hi.x()), y, z};
  }

 private:
  std::uint64_t state_;
};

Eigen::Vector3f hsv(float h, float s, float v) {
  const float c = v * s, hp = std::fmod(h, 1.0f) * 6.0f,
              x = c * (1 - std::abs(std::fmod(hp, 2.0f) - 1));
  Eigen::Vector3f rgb = hp < 1   ? Eigen::Vector3f(c, x, 0)
                        : hp < 2 ? Eigen::Vector3f(x, c, 0)
                        : hp < 3 ? Eigen::Vector3f(0, c, x)
                        : hp < 4 ? Eigen::Vector3f(0, x, c)
                        : hp < 5 ? Eigen::Vector3f(x, 0, c)
                                 : Eigen::Vector3f(c, 0, x);
  return rgb + Eigen::Vector3f::Constant(v - c);
}

Material random_material(Random& rng, Pattern pattern, float scale) {
  Material m;
  m.pattern = pattern;
  const float hue = rng.uniform(0, 1);
  const float value_a = rng.uniform(0.55f, 0.9f), saturation_a = rng.uniform(0.15f, 0.6f);
  m.color_a = hsv(hue, saturation_a, value_a);
  const float value_b = rng.uniform(0.1f, 0.45f), saturation_b = rng.uniform(0.3f, 0.8f);
  m.color_b = hsv(hue + rng.uniform(0.1f, 0.5f), saturation_b, value_b);
  m.scale = scale;
  m.seed = std::uint32_t(rng.next());
  return m;
}

void keep_nearest(float t, const Eigen::Vector3f& normal, int material, Hit* hit) {
  if (t > kEpsilon && t < hit->t) {
    hit->t = t;
    hit->normal = normal;
    hit->material = material;
  }
}

void intersect_sphere(const Ray& r, const Sphere& s, Hit* hit) {
  const Eigen::Vector3f oc = r.origin - s.center;
  const float b = oc.dot(r.direction);
  const float c = oc.squaredNorm() - s.radius * s.radius;
  const float disc = b * b - c;
  if (disc < 0) return;
  const float sq = std::sqrt(disc);
  float t = -b - sq;
  if (t <= kEpsilon) t = -b + sq;
  if (t <= kEpsilon || t >= hit->t) return;
  keep_nearest(t, (r.origin + t * r.direction - s.center) / s.radius, s.material, hit);
}

void intersect_box(const Ray& r, const Box& b, Hit* hit) {
  const float c = std::cos(b.yaw), s = std::sin(b.yaw);
  // Into box coordinates (rotation about y by -yaw).
  const Eigen::Vector3f d0 = r.origin - b.center;
  const Eigen::Vector3f o(c * d0.x() - s * d0.z(), d0.y(), s * d0.x() + c * d0.z());
  const Eigen::Vector3f d(c * r.direction.x() - s * r.direction.z(), r.direction.y(),
                          s * r.direction.x() + c * r.direction.z());
  float t_near = -std::numeric_limits<float>::infinity(),
        t_far = std::numeric_limits<float>::infinity();
  int axis = 0;
  float sign = 1;
  for (int i = 0; i < 3; ++i) {
    const float inv = 1.0f / d[i];
    float t0 = (-b.half_size[i] - o[i]) * inv, t1 = (b.half_size[i] - o[i]) * inv;
    float face_sign = -1;  // entering through the -half face when d > 0
    if (t0 > t1) {
      std::swap(t0, t1);
      face_sign = 1;
    }
    if (t0 > t_near) {
      t_near = t0;
      axis = i;
      sign = face_sign;
    }
    t_far = std::min(t_far, t1);
  }
  if (t_near > t_far || t_near <= kEpsilon || t_near >= hit->t) return;
  Eigen::Vector3f n_local = Eigen::Vector3f::Zero();
  n_local[axis] = sign;
  const Eigen::Vector3f n(c * n_local.x() + s * n_local.z(), n_local.y(),
                          -s * n_local.x() + c * n_local.z());
  keep_nearest(t_near, n, b.material, hit);
}

void intersect_pole(const Ray& r, const Pole& p, const Room& room, Hit* hit) {
  const float ox = r.origin.x() - p.x, oz = r.origin.z() - p.z;
  const float dx = r.direction.x(), dz = r.direction.z();
  const float a = dx * dx + dz * dz;
  if (a < 1e-12f) return;
  const float b = ox * dx + oz * dz, c = ox * ox + oz * oz - p.radius * p.radius;
  const float disc = b * b - a * c;
  if (disc < 0) return;
  const float t = (-b - std::sqrt(disc)) / a;
  if (t <= kEpsilon || t >= hit->t) return;
  const float y = r.origin.y() + t * r.direction.y();
  if (y < room.min.y() || y > room.max.y()) return;
  const float hx = ox + t * dx, hz = oz + t * dz;
  keep_nearest(t, Eigen::Vector3f(hx, 0, hz) / p.radius, p.material, hit);
}

void intersect_room(const Ray& r, const Room& room, Hit* hit) {
  float t_exit = std::numeric_limits<float>::infinity();
  int axis = 0;
  for (int i = 0; i < 3; ++i) {
    if (r.direction[i] == 0.0f) continue;
    const float bound = r.direction[i] > 0 ? room.max[i] : room.min[i];
    const float t = (bound - r.origin[i]) / r.direction[i];
    if (t < t_exit) {
      t_exit = t;
      axis = i;
    }
  }
  Eigen::Vector3f n = Eigen::Vector3f::Zero();
  n[axis] = r.direction[axis] > 0 ? -1.0f : 1.0f;
  const int material = axis != 1             ? room.wall_material
                       : r.direction.y() > 0 ? room.floor_material
                                             : room.ceiling_material;
  keep_nearest(t_exit, n, material, hit);
}

float distance_to_path(const Eigen::Vector3f& p, const std::vector<Eigen::Vector3f>& path) {
  float d = std::numeric_limits<float>::infinity();
  for (const auto& q : path) d = std::min(d, (p - q).norm());
  return d;
}

}  // namespace

Scene Scene::hall(std::uint64_t seed, const std::vector<Eigen::Vector3f>& keep_clear,
                  float clearance, float near_distance) {
  // Every draw from rng is its own statement: C++ leaves the order in which a call's arguments
  // are evaluated to the compiler (GCC and clang differ), so two draws in one call would give
  // each compiler a different scene for the same seed. The order below is the one GCC used,
  // so scenes are those of earlier releases.
  Random rng(seed);
  Scene s;
  // A hall up to about 25 m x 21 m x 4.5 m: the far corners stay within 20 m of the rig's path.
  s.room_.min = rng.uniform_zyx({-10.5f, -3.4f, -7.5f}, {-9.0f, -2.6f, -6.0f});
  s.room_.max = rng.uniform_zyx({9.5f, 1.3f, 12.5f}, {11.0f, 1.6f, 14.0f});
  auto add_material = [&](Material m) {
    s.materials_.push_back(m);
    return int(s.materials_.size()) - 1;
  };
  // A new material: its scale drawn from [lo, hi] first, then its pattern drawn from the
  // `count` patterns at `patterns` (no draw when count is 1).
  auto new_material = [&](const Pattern* patterns, int count, float lo, float hi) {
    const float scale = rng.uniform(lo, hi);
    const Pattern pattern = count > 1 ? patterns[rng.index(count)] : patterns[0];
    return add_material(random_material(rng, pattern, scale));
  };
  const Pattern blotches = Pattern::kBlotches, tiles = Pattern::kTiles;
  s.room_.wall_material = new_material(&blotches, 1, 0.8f, 1.4f);
  s.room_.floor_material = new_material(&tiles, 1, 0.5f, 0.8f);
  s.room_.ceiling_material = add_material(random_material(rng, Pattern::kPlain, 1.0f));
  s.light_ =
      Eigen::Vector3f(0.5f * (s.room_.min.x() + s.room_.max.x()), s.room_.min.y() + 0.3f, 2.0f);

  const Pattern object_patterns[] = {Pattern::kNoise, Pattern::kStripes, Pattern::kNoise,
                                     Pattern::kTiles, Pattern::kPlain};
  std::vector<Eigen::Vector4f> placed;  // bounding circles (x, z, radius) and unused w
  auto fits = [&](const Eigen::Vector3f& c, float radius) {
    if (c.x() - radius < s.room_.min.x() + 0.3f || c.x() + radius > s.room_.max.x() - 0.3f ||
        c.z() - radius < s.room_.min.z() + 0.3f || c.z() + radius > s.room_.max.z() - 0.3f) {
      return false;
    }
    // Vertical extent is bounded by the room, so a 2D test of the rig path is conservative.
    for (const auto& q : keep_clear) {
      if (Eigen::Vector2f(c.x() - q.x(), c.z() - q.z()).norm() < radius + clearance) return false;
    }
    for (const auto& p : placed) {
      if (Eigen::Vector2f(c.x() - p.x(), c.z() - p.y()).norm() < radius + p.z() + 0.1f)
        return false;
    }
    return true;
  };
  auto place = [&](float radius, auto make) {
    for (int attempt = 0; attempt < 200; ++attempt) {
      // Half the objects within 4 m of the start, the rest anywhere in the hall.
      const bool near = rng.index(2) == 0;
      // On the floor (y = 0), z drawn first.
      const Eigen::Vector2f lo =
          near ? Eigen::Vector2f(-4, -4) : Eigen::Vector2f(s.room_.min.x(), s.room_.min.z());
      const Eigen::Vector2f hi =
          near ? Eigen::Vector2f(4, 4) : Eigen::Vector2f(s.room_.max.x(), s.room_.max.z());
      const float z = rng.uniform(lo.y(), hi.y());
      const Eigen::Vector3f c(rng.uniform(lo.x(), hi.x()), 0, z);
      if (fits(c, radius)) {
        placed.emplace_back(c.x(), c.z(), radius, 0);
        make(c);
        return;
      }
    }
  };
  const float floor_y = s.room_.max.y();
  for (int i = 0; i < 8; ++i) {
    const Eigen::Vector3f half = rng.uniform_zyx({0.15f, 0.15f, 0.15f}, {0.8f, 1.1f, 0.8f});
    const int mat = new_material(object_patterns, 5, 0.15f, 0.5f);
    const float yaw = rng.uniform(0, 3.14159f);
    place(std::hypot(half.x(), half.z()), [&](const Eigen::Vector3f& c) {
      s.boxes_.push_back({Eigen::Vector3f(c.x(), floor_y - half.y(), c.z()), half, yaw, mat});
    });
  }
  for (int i = 0; i < 5; ++i) {
    const float radius = rng.uniform(0.15f, 0.7f);
    const float lift = rng.index(2) ? 0.0f : rng.uniform(0.3f, 1.5f);
    const int mat = new_material(object_patterns, 4, 0.1f, 0.35f);
    place(radius, [&](const Eigen::Vector3f& c) {
      s.spheres_.push_back({Eigen::Vector3f(c.x(), floor_y - radius - lift, c.z()), radius, mat});
    });
  }
  for (int i = 0; i < 6; ++i) {
    const float radius = rng.uniform(0.025f, 0.06f);
    const Pattern stripes = Pattern::kStripes;
    const int mat = new_material(&stripes, 1, 0.1f, 0.3f);
    place(radius, [&](const Eigen::Vector3f& c) {
      s.poles_.push_back({c.x(), c.z(), radius, mat});
    });
  }
  // One near sphere below and behind the start of the path (the path itself runs forward).
  if (!keep_clear.empty()) {
    const float radius = 0.15f;
    const Eigen::Vector3f dir = Eigen::Vector3f(0.0f, 0.35f, -1.0f).normalized();
    Eigen::Vector3f c = keep_clear[0] + dir * (near_distance + radius);
    for (int k = 0; k < 50 && distance_to_path(c, keep_clear) < near_distance + radius; ++k) {
      c += dir * 0.05f;  // push out until the whole path keeps its clearance
    }
    const int mat = add_material(random_material(rng, Pattern::kNoise, 0.08f));
    s.spheres_.push_back({c, radius, mat});
  }
  return s;
}

bool Scene::intersect(const Ray& ray, Hit* hit) const {
  hit->t = std::numeric_limits<float>::infinity();
  intersect_room(ray, room_, hit);
  for (const Box& b : boxes_) intersect_box(ray, b, hit);
  for (const Sphere& sp : spheres_) intersect_sphere(ray, sp, hit);
  for (const Pole& p : poles_) intersect_pole(ray, p, room_, hit);
  return std::isfinite(hit->t);
}

Eigen::Vector3f Scene::shade(const Ray& ray, const Hit& hit, float pixel_angle) const {
  const Eigen::Vector3f p = ray.origin + hit.t * ray.direction;
  const float cos_incidence = std::max(std::abs(hit.normal.dot(ray.direction)), 0.2f);
  const float footprint = hit.t * pixel_angle / cos_incidence;
  const Eigen::Vector3f base = albedo(materials_[hit.material], p, hit.normal, footprint);
  // Lambertian, no shadows: the colour of a point does not depend on who looks at it.
  const Eigen::Vector3f to_light = (light_ - p).normalized();
  const float diffuse = std::max(hit.normal.dot(to_light), 0.0f);
  const float sky = 0.5f + 0.5f * std::max(-hit.normal.y(), 0.0f);  // light from above
  return (base * (0.35f + 0.45f * diffuse + 0.2f * sky)).cwiseMin(1.0f);
}

}  // namespace omnisweep::synthetic
