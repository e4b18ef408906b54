#include "server/stitch/region_planes.h"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

namespace omnisweep::stitch {
namespace {

using Vec3 = Eigen::Vector3d;

// The panorama's unit rays, in plane_fill.comp's frame (a plane's inverse distance is a . r in
// any frame; the surround test only needs one tangent basis per ray).
class Rays {
 public:
  Rays(int width, int height) : width_(width), col_(width), row_(height) {
    for (int x = 0; x < width; ++x) {
      const double theta = 2.0 * std::numbers::pi * (x + 0.5) / width;
      col_[x] = {std::cos(theta), std::sin(theta)};
    }
    for (int y = 0; y < height; ++y) {
      const double phi = std::numbers::pi * (y + 0.5) / height;
      row_[y] = {std::sin(phi), std::cos(phi)};
    }
  }
  Vec3 operator()(int x, int y) const {
    return {row_[y][0] * col_[x][0], row_[y][0] * col_[x][1], row_[y][1]};
  }
  Vec3 at(std::size_t i) const { return (*this)(int(i % width_), int(i / width_)); }

 private:
  std::size_t width_;
  std::vector<std::array<double, 2>> col_;  // cos, sin of the longitude
  std::vector<std::array<double, 2>> row_;  // sin, cos of the colatitude
};

// The PCG hash (Jarzynski and Olano, "Hash Functions for GPU Rendering", 2020): RANSAC's draws,
// reproducible and free of state, as a GPU kernel would draw them.
std::uint32_t mix(std::uint32_t x) {
  const std::uint32_t state = x * 747796405u + 2891336453u;
  const std::uint32_t word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
  return (word >> 22u) ^ word;
}

// Union-find over the pixels (path halving).
int find(std::vector<int>& parent, int i) {
  while (parent[i] != i) {
    parent[i] = parent[parent[i]];
    i = parent[i];
  }
  return i;
}

void unite(std::vector<int>& parent, int a, int b) {
  a = find(parent, a);
  b = find(parent, b);
  if (a != b) parent[std::max(a, b)] = std::min(a, b);
}

// The regions: 8-connected components of `low` (the panorama wraps left to right) of at least
// min_pixels pixels, numbered 0..; -1 elsewhere.
std::vector<int> label_regions(const std::vector<char>& low, int w, int h, int min_pixels,
                               int* count) {
  const int n = w * h;
  std::vector<int> parent(n);
  for (int i = 0; i < n; ++i) parent[i] = i;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const int i = y * w + x;
      if (!low[i]) continue;
      const int left = y * w + (x + w - 1) % w;
      if (low[left]) unite(parent, i, left);
      if (y == 0) continue;
      for (int dx = -1; dx <= 1; ++dx) {
        const int j = (y - 1) * w + (x + dx + w) % w;
        if (low[j]) unite(parent, i, j);
      }
    }
  }
  std::vector<int> size(n, 0);
  for (int i = 0; i < n; ++i)
    if (low[i]) ++size[find(parent, i)];
  std::vector<int> index(n, -1), label(n, -1);
  *count = 0;
  for (int i = 0; i < n; ++i) {
    if (!low[i]) continue;
    const int root = find(parent, i);
    if (size[root] < min_pixels) continue;
    if (index[root] < 0) index[root] = (*count)++;
    label[i] = index[root];
  }
  return label;
}

struct Support {
  Vec3 ray;
  double v;  // inverse distance, m^-1
};

// Per region, the confident pixels within `rim` pixels of it (outside it: its rim and holes).
std::vector<std::vector<Support>> gather_support(const std::vector<int>& label, int regions,
                                                 const float* distance, const float* confidence,
                                                 const Rays& rays, int w, int h,
                                                 const RegionPlaneParams& p) {
  std::vector<std::vector<Support>> support(regions);
  // Per row, the count of region pixels left of each column: whether the square around a pixel
  // holds any is 2 rim + 1 lookups, and the disk is searched only where it does.
  std::vector<int> prefix(std::size_t(w + 1) * h, 0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      prefix[std::size_t(y) * (w + 1) + x + 1] =
          prefix[std::size_t(y) * (w + 1) + x] + (label[std::size_t(y) * w + x] >= 0);
  auto row_has = [&](int y, int x0, int x1) {  // columns x0..x1, wrapping
    const int* row = &prefix[std::size_t(y) * (w + 1)];
    if (x1 - x0 + 1 >= w) return row[w] > 0;
    const int a = (x0 % w + w) % w, b = (x1 % w + w) % w;
    return a <= b ? row[b + 1] - row[a] > 0 : row[w] - row[a] + row[b + 1] > 0;
  };
  const int r2 = p.rim * p.rim;
  std::vector<int> seen;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const std::size_t i = std::size_t(y) * w + x;
      if (label[i] >= 0 || !(distance[i] > 0.0f) || confidence[i] < p.support) continue;
      bool near = false;
      for (int yy = std::max(0, y - p.rim); yy <= std::min(h - 1, y + p.rim) && !near; ++yy)
        near = row_has(yy, x - p.rim, x + p.rim);
      if (!near) continue;
      seen.clear();
      for (int dy = -p.rim; dy <= p.rim; ++dy) {
        const int yy = y + dy;
        if (yy < 0 || yy >= h) continue;
        for (int dx = -p.rim; dx <= p.rim; ++dx) {
          if (dx * dx + dy * dy > r2) continue;
          const int l = label[std::size_t(yy) * w + (x + dx + w) % w];
          if (l >= 0 && std::find(seen.begin(), seen.end(), l) == seen.end()) seen.push_back(l);
        }
      }
      for (const int l : seen) support[l].push_back({rays(x, y), 1.0 / distance[i]});
    }
  }
  return support;
}

bool inlier(const Vec3& a, const Support& s, double tau) {
  return std::abs(a.dot(s.ray) - s.v) < tau * s.v;
}

struct Plane {
  Vec3 a;
  std::vector<Vec3> inliers;  // up to surround_samples of them, strided
};

// Sequential RANSAC over one region's support: of `draws` hypotheses through three supports, the
// one with the best MSAC score (each support within tau scores 1 - (residual / tau v)^2, so that
// a plane through the middle of its inliers beats one at the edge of the band), refitted three
// times by least squares on its inliers; its inliers are removed, and again, while a plane has
// max(30, support / min_inlier_fraction) inliers.
std::vector<Plane> find_planes(const std::vector<Support>& support, int region,
                               const RegionPlaneParams& p) {
  std::vector<Plane> planes;
  std::vector<int> alive(support.size());
  for (std::size_t i = 0; i < support.size(); ++i) alive[i] = int(i);
  const std::size_t needed =
      std::max<std::size_t>(30, support.size() / std::size_t(p.min_inlier_fraction));
  for (int k = 0; k < p.max_planes && alive.size() >= needed; ++k) {
    const std::size_t stride = (alive.size() + p.max_scored - 1) / p.max_scored;
    Vec3 best_a = Vec3::Zero();
    double best = -1;
    for (int d = 0; d < p.draws; ++d) {
      Eigen::Matrix3d m;
      Vec3 v;
      for (int t = 0; t < 3; ++t) {
        const std::uint32_t h =
            mix(std::uint32_t(region) * 0x9e3779b9u ^
                mix(std::uint32_t(k) * 0x85ebca6bu ^ mix(std::uint32_t(3 * d + t))));
        const Support& s = support[alive[h % alive.size()]];
        m.row(t) = s.ray.transpose();
        v[t] = s.v;
      }
      if (std::abs(m.determinant()) < 1e-6) continue;
      const Vec3 a = m.partialPivLu().solve(v);
      double count = 0;
      for (std::size_t j = 0; j < alive.size(); j += stride) {
        const Support& s = support[alive[j]];
        const double e = (a.dot(s.ray) - s.v) / (p.tau * s.v);
        count += std::max(0.0, 1.0 - e * e);
      }
      if (count > best) {
        best = count;
        best_a = a;
      }
    }
    if (best < 0) break;
    auto count_inliers = [&](const Vec3& a) {
      std::size_t c = 0;
      for (const int j : alive) c += inlier(a, support[j], p.tau);
      return c;
    };
    if (count_inliers(best_a) < needed) break;
    for (int refit = 0; refit < 3; ++refit) {
      Eigen::Matrix3d m = Eigen::Matrix3d::Zero();
      Vec3 rhs = Vec3::Zero();
      for (const int j : alive) {
        if (!inlier(best_a, support[j], p.tau)) continue;
        m += support[j].ray * support[j].ray.transpose();
        rhs += support[j].v * support[j].ray;
      }
      const Eigen::JacobiSVD<Eigen::Matrix3d> svd(m, Eigen::ComputeFullU | Eigen::ComputeFullV);
      const Vec3 a = svd.solve(rhs);
      if (!a.allFinite()) break;
      best_a = a;
    }
    Plane plane{best_a, {}};
    std::vector<int> rest, in;
    for (const int j : alive) (inlier(best_a, support[j], p.tau) ? in : rest).push_back(j);
    const std::size_t step = (in.size() + p.surround_samples - 1) / p.surround_samples;
    for (std::size_t j = 0; j < in.size(); j += std::max<std::size_t>(1, step))
      plane.inliers.push_back(support[in[j]].ray);
    planes.push_back(std::move(plane));
    alive = std::move(rest);
  }
  return planes;
}

// Whether the plane's inliers lie in at least three of the four quadrants of the tangent plane
// at `r` (on its hemisphere): `r` is inside what they span.
bool surrounds(const Plane& plane, const Vec3& r) {
  Vec3 e1 = Vec3::UnitZ().cross(r);
  if (e1.norm() < 1e-6) e1 = Vec3::UnitX();
  e1.normalize();
  const Vec3 e2 = r.cross(e1);
  unsigned quadrants = 0;
  for (const Vec3& t : plane.inliers) {
    if (t.dot(r) <= 0.0) continue;
    const double u = t.dot(e1), w = t.dot(e2);
    quadrants |= u >= 0 ? (w >= 0 ? 1u : 2u) : (w >= 0 ? 4u : 8u);
    if (quadrants == 15u) break;
  }
  int n = 0;
  for (unsigned q = quadrants; q; q >>= 1) n += int(q & 1u);
  return n >= 3;
}

void check(const RegionPlaneParams& p) {
  auto bad = [](const char* name, double value, const char* range) {
    throw std::invalid_argument("RegionPlaneParams::" + std::string(name) + " is " +
                                std::to_string(value) + "; it must be " + range);
  };
  if (!(p.fill_below > 0 && p.fill_below < 1)) bad("fill_below", p.fill_below, "in (0, 1)");
  if (!(p.support >= p.fill_below && p.support <= 1))
    bad("support", p.support, "in [fill_below, 1]");
  if (p.rim < 1) bad("rim", p.rim, "at least 1");
  if (p.min_pixels < 1) bad("min_pixels", p.min_pixels, "at least 1");
  if (p.max_planes < 1 || p.max_planes > 32) bad("max_planes", p.max_planes, "in [1, 32]");
  if (p.draws < 1) bad("draws", p.draws, "at least 1");
  if (p.max_scored < 3) bad("max_scored", p.max_scored, "at least 3");
  if (!(p.tau > 0 && p.tau < 1)) bad("tau", p.tau, "in (0, 1)");
  if (p.min_inlier_fraction < 1) bad("min_inlier_fraction", p.min_inlier_fraction, "at least 1");
  if (p.cell < 1) bad("cell", p.cell, "at least 1");
  if (p.surround_samples < 1) bad("surround_samples", p.surround_samples, "at least 1");
}

}  // namespace

RegionPlaneParams RegionPlaneParams::for_width(int width) {
  RegionPlaneParams p;
  const double scale = double(width) / 2048.0;
  p.rim = std::max(1, int(std::lround(p.rim * scale)));
  p.min_pixels = std::max(1, int(std::lround(p.min_pixels * scale * scale)));
  p.cell = std::max(1, int(std::lround(p.cell * scale)));
  return p;
}

FloatImage region_planes_cpu(const FloatImage& distance, const FloatImage& confidence,
                             const RegionPlaneParams& params, double min_distance,
                             double max_distance) {
  if (confidence.width() != distance.width() || confidence.height() != distance.height())
    throw std::invalid_argument(
        "region planes: the distance is " + std::to_string(distance.width()) + "x" +
        std::to_string(distance.height()) + ", the confidence " +
        std::to_string(confidence.width()) + "x" + std::to_string(confidence.height()));
  if (!(min_distance > 0 && max_distance > min_distance))
    throw std::invalid_argument("region planes: the distance range must be 0 < min < max");
  check(params);
  const int w = distance.width(), h = distance.height();
  const float* d = distance.data();
  const float* c = confidence.data();
  FloatImage out(w, h);
  std::copy(d, d + distance.size(), out.data());
  if (w == 0 || h == 0) return out;

  std::vector<char> low(distance.size());
  for (std::size_t i = 0; i < low.size(); ++i) low[i] = d[i] > 0.0f && c[i] < params.fill_below;
  int regions = 0;
  const std::vector<int> label = label_regions(low, w, h, params.min_pixels, &regions);
  if (regions == 0) return out;
  const Rays rays(w, h);
  const auto support = gather_support(label, regions, d, c, rays, w, h, params);

  const int cells_x = (w + params.cell - 1) / params.cell;
  const int cells_y = (h + params.cell - 1) / params.cell;
  auto cell_of = [&](std::size_t i) {
    return (i / w / params.cell) * cells_x + (i % w) / params.cell;
  };
  // Each region's pixels, in one pass over the panorama.
  std::vector<std::vector<std::size_t>> pixels(regions);
  for (std::size_t i = 0; i < label.size(); ++i)
    if (label[i] >= 0) pixels[label[i]].push_back(i);
  const double v_min = 1.0 / max_distance, v_max = 1.0 / min_distance;
  for (int r = 0; r < regions; ++r) {
    const std::vector<Plane> planes = find_planes(support[r], r, params);
    if (planes.empty()) continue;
    // Per cell the region touches, a bit per plane that surrounds the cell's centre ray.
    std::vector<std::uint32_t> surround(std::size_t(cells_x) * cells_y, 0);
    std::vector<char> touched(surround.size(), 0);
    for (const std::size_t i : pixels[r]) touched[cell_of(i)] = 1;
    for (int cy = 0; cy < cells_y; ++cy) {
      for (int cx = 0; cx < cells_x; ++cx) {
        const std::size_t cell = std::size_t(cy) * cells_x + cx;
        if (!touched[cell]) continue;
        const Vec3 ray = rays(std::min(w - 1, cx * params.cell + params.cell / 2),
                              std::min(h - 1, cy * params.cell + params.cell / 2));
        for (std::size_t k = 0; k < planes.size(); ++k)
          if (surrounds(planes[k], ray)) surround[cell] |= 1u << k;
      }
    }
    for (const std::size_t i : pixels[r]) {
      const std::uint32_t bits = surround[cell_of(i)];
      if (!bits) continue;
      const Vec3 ray = rays.at(i);
      const double own = 1.0 / d[i];
      double pick = 0.0, nearest = INFINITY;
      for (std::size_t k = 0; k < planes.size(); ++k) {
        if (!(bits & (1u << k))) continue;
        const double pv = planes[k].a.dot(ray);
        if (pv > 0.0 && std::abs(pv - own) < nearest) {
          nearest = std::abs(pv - own);
          pick = pv;
        }
      }
      if (!(pick > 0.0)) continue;
      const double alpha = 1.0 - c[i] / params.fill_below;
      const double v = std::clamp(alpha * pick + (1.0 - alpha) * own, v_min, v_max);
      out.data()[i] = float(1.0 / v);
    }
  }
  return out;
}

}  // namespace omnisweep::stitch
