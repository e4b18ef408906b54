// The region planes' test scene (region_planes_test.cc, region_planes_gpu_test.cc): a box room
// seen from inside, exact and confident but where a test makes it unconfident and 25 % too far.
#pragma once

#include <cmath>
#include <cstddef>
#include <functional>
#include <numbers>
#include <vector>

#include "omnisweep/image/image.h"

namespace omnisweep::stitch::region_test {

inline constexpr int kW = 256, kH = 128;
inline constexpr double kMinDistance = 0.55, kMaxDistance = 100.0;

struct Hit {
  double v;        // inverse distance
  int plane;       // 0 ceiling, 1 floor, 2-5 walls
  double x, y, z;  // the point, metres
};

// A box room around the viewpoint: ceiling 1.5 m above, floor 1.2 m below, walls at x = -3, +3
// and y = -2.5, +2.5 (plane_fill.comp's frame: z up). Seen from inside, a ray's surface is the
// nearest plane it meets: the largest inverse distance among the planes.
inline Hit hit(int x, int y) {
  const double theta = 2.0 * std::numbers::pi * (x + 0.5) / kW;
  const double phi = std::numbers::pi * (y + 0.5) / kH;
  const double r[3] = {std::sin(phi) * std::cos(theta), std::sin(phi) * std::sin(theta),
                       std::cos(phi)};
  const double planes[6][3] = {{0, 0, 1 / 1.5}, {0, 0, -1 / 1.2}, {-1 / 3.0, 0, 0},
                               {1 / 3.0, 0, 0}, {0, -1 / 2.5, 0}, {0, 1 / 2.5, 0}};
  Hit h{-1, -1, 0, 0, 0};
  for (int k = 0; k < 6; ++k) {
    const double v = planes[k][0] * r[0] + planes[k][1] * r[1] + planes[k][2] * r[2];
    if (v > h.v) h = {v, k, r[0] / v, r[1] / v, r[2] / v};
  }
  return h;
}

struct Scene {
  FloatImage truth;  // inverse distance
  FloatImage distance;
  FloatImage confidence;
  std::vector<bool> low;
};

// Confident (0.6) and exact everywhere but where `low` holds: confidence 0.01 and the distance
// 25 % too far (the ISB filter's fill). `hole` pixels have no distance.
inline Scene make_scene(const std::function<bool(const Hit&, int, int)>& low,
                        const std::function<bool(const Hit&, int, int)>& hole = {}) {
  Scene s{FloatImage(kW, kH), FloatImage(kW, kH), FloatImage(kW, kH),
          std::vector<bool>(std::size_t(kW) * kH)};
  for (int y = 0; y < kH; ++y) {
    for (int x = 0; x < kW; ++x) {
      const std::size_t i = std::size_t(y) * kW + x;
      const Hit h = hit(x, y);
      s.truth.data()[i] = float(h.v);
      if (hole && hole(h, x, y)) {
        s.distance.data()[i] = 0.0f;
        s.confidence.data()[i] = 0.0f;
        continue;
      }
      s.low[i] = low(h, x, y);
      s.distance.data()[i] = float(1.0 / (s.low[i] ? 0.8 * h.v : h.v));
      s.confidence.data()[i] = s.low[i] ? 0.01f : 0.6f;
    }
  }
  return s;
}

// The ceiling more than 0.6 m from the walls: a plain region with a confident rim on its plane.
inline bool plain_ceiling(const Hit& h, int, int) {
  return h.plane == 0 && std::abs(h.x) < 2.4 && std::abs(h.y) < 1.9;
}

}  // namespace omnisweep::stitch::region_test
