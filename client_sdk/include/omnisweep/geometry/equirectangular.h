// The equirectangular panorama convention (ALGORITHM.md §5), in the rig frame:
//   pixel (x, y) of a W x H panorama has latitude  phi   = (y + 0.5) * pi / H - pi / 2
//                                        longitude theta = (x + 0.5) * 2 pi / W + pi
//   direction = (cos phi sin theta, sin phi, cos phi cos theta)
// so the centre column looks along +z, the left edge along -z, and the top row up (-y).
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <numbers>

namespace omnisweep {

template <typename Scalar>
Eigen::Matrix<Scalar, 3, 1> equirect_direction(Scalar x, Scalar y, int width, int height) {
  constexpr Scalar pi = std::numbers::pi_v<Scalar>;
  const Scalar phi = (y + Scalar(0.5)) * pi / Scalar(height) - pi / Scalar(2);
  const Scalar theta = (x + Scalar(0.5)) * Scalar(2) * pi / Scalar(width) + pi;
  return {std::cos(phi) * std::sin(theta), std::sin(phi), std::cos(phi) * std::cos(theta)};
}

// Inverse of equirect_direction for any non-zero direction; x in [-0.5, W - 0.5).
template <typename Scalar>
Eigen::Matrix<Scalar, 2, 1> equirect_pixel(const Eigen::Matrix<Scalar, 3, 1>& direction, int width,
                                           int height) {
  constexpr Scalar pi = std::numbers::pi_v<Scalar>;
  const Eigen::Matrix<Scalar, 3, 1> d = direction.normalized();
  const Scalar phi = std::asin(std::clamp(d.y(), Scalar(-1), Scalar(1)));
  Scalar theta = std::atan2(d.x(), d.z()) - pi;  // in (-2 pi, 0]
  if (theta < Scalar(0)) theta += Scalar(2) * pi;
  Scalar x = theta * Scalar(width) / (Scalar(2) * pi) - Scalar(0.5);
  if (x >= Scalar(width) - Scalar(0.5)) x -= Scalar(width);
  const Scalar y = (phi + pi / Scalar(2)) * Scalar(height) / pi - Scalar(0.5);
  return {x, y};
}

}  // namespace omnisweep
