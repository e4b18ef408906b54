// The equirectangular panorama's rays as the plane fill and region planes kernels read them
// (plane_fill.glsl, region_planes.glsl): per column (cos, sin) of the longitude, then per row
// (sin, cos) of the colatitude, pixel centres, in float. A ray is
// (sin phi cos theta, sin phi sin theta, cos phi): z up.
#pragma once

#include <cmath>
#include <numbers>
#include <vector>

namespace omnisweep::stitch {

inline std::vector<float> panorama_ray_table(int width, int height) {
  std::vector<float> table;
  table.reserve(2 * std::size_t(width + height));
  for (int x = 0; x < width; ++x) {
    const double theta = 2.0 * std::numbers::pi * (x + 0.5) / width;
    table.insert(table.end(), {float(std::cos(theta)), float(std::sin(theta))});
  }
  for (int y = 0; y < height; ++y) {
    const double phi = std::numbers::pi * (y + 0.5) / height;
    table.insert(table.end(), {float(std::sin(phi)), float(std::cos(phi))});
  }
  return table;
}

}  // namespace omnisweep::stitch
