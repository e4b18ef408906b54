#include "server/stitch/region_planes.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "server/stitch/region_planes_math.h"
#include "server/stitch/same_size.h"

namespace omnisweep::stitch {

RegionPlaneParams RegionPlaneParams::for_width(int width) {
  RegionPlaneParams p;
  const double scale = double(width) / 2048.0;
  p.block = std::max(1, int(std::lround(p.block * scale)));
  p.rim = std::max(1, int(std::lround(8.0 * scale / p.block)));
  p.min_pixels = std::max(1, int(std::lround(p.min_pixels * scale * scale)));
  return p;
}

void RegionPlaneParams::check() const {
  auto bad = [](const char* name, double value, const std::string& range) {
    throw std::invalid_argument("RegionPlaneParams::" + std::string(name) + " is " +
                                std::to_string(value) + "; it must be " + range);
  };
  if (!(fill_below > 0 && fill_below < 1)) bad("fill_below", fill_below, "in (0, 1)");
  if (!(support >= fill_below && support <= 1)) bad("support", support, "in [fill_below, 1]");
  if (block < 1 || block > 16) bad("block", block, "in [1, 16]");
  if (rim < 0 || rim > 8) bad("rim", rim, "in [0, 8]");
  if (min_pixels < 1) bad("min_pixels", min_pixels, "at least 1");
  if (max_regions < 1 || max_regions > kRegionPlaneMaxRegions)
    bad("max_regions", max_regions, "in [1, " + std::to_string(kRegionPlaneMaxRegions) + "]");
  if (max_planes < 1 || max_planes > kRegionPlaneMaxPlanes)
    bad("max_planes", max_planes, "in [1, " + std::to_string(kRegionPlaneMaxPlanes) + "]");
  if (draws < 1 || draws > 65536) bad("draws", draws, "in [1, 65536]");
  if (!(tau > 0 && tau < 1)) bad("tau", tau, "in (0, 1)");
  if (min_inliers < 3) bad("min_inliers", min_inliers, "at least 3");
  if (min_inlier_fraction < 1) bad("min_inlier_fraction", min_inlier_fraction, "at least 1");
  if (!(surround_angle_deg > 0 && surround_angle_deg <= 90))
    bad("surround_angle_deg", surround_angle_deg, "in (0, 90]");
}

namespace {

using region_math::Vec3f;

// Union-find over the blocks; the root of a component is its least index (the larger root is
// linked under the smaller), as the GPU's atomicMin linking leaves it.
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

struct Region {
  int root = 0;
  std::uint32_t supports = 0;                            // support entries before sampling
  std::array<std::uint32_t, 256> bins{};                 // of their hashes' top 8 bits
  std::vector<std::array<std::uint32_t, 2>> candidates;  // (hash, block)
  std::vector<Vec3f> rays;
  std::vector<float> v;
  std::vector<int> tag;  // the plane a support is an inlier of, -1 none
  std::vector<Vec3f> planes;
};

// Step 4 (region_ransac_step.comp): sequential RANSAC over the region's sample.
void find_planes(Region& r, const RegionPlaneParams& p) {
  const int n = int(r.rays.size());
  r.tag.assign(n, -1);
  if (n < 3) return;
  const int needed =
      region_math::needed_inliers(n, r.supports, p.min_inliers, p.min_inlier_fraction);
  const float tau = float(p.tau);
  std::vector<int> alive(n);
  for (int i = 0; i < n; ++i) alive[i] = i;
  for (int k = 0; k < p.max_planes; ++k) {
    const int count = int(alive.size());
    if (count < needed || count < 3) break;
    float best = -1.0f;
    Vec3f best_a{};
    for (int d = 0; d < p.draws; ++d) {
      int j[3];
      for (int t = 0; t < 3; ++t)
        j[t] = alive[region_math::draw(std::uint32_t(r.root), std::uint32_t(k),
                                       std::uint32_t(3 * d + t)) %
                     std::uint32_t(count)];
      Vec3f a;
      if (!region_math::solve(r.rays[j[0]], r.rays[j[1]], r.rays[j[2]],
                              {r.v[j[0]], r.v[j[1]], r.v[j[2]]}, 1e-6f, a))
        continue;
      float score = 0.0f;
      for (int i = 0; i < count; ++i)
        score += region_math::msac(a, r.rays[alive[i]], r.v[alive[i]], tau);
      if (score > best) {
        best = score;
        best_a = a;
      }
    }
    if (best < 0.0f) break;
    auto inlier = [&](const Vec3f& a, int i) {
      return region_math::is_inlier(a, r.rays[i], r.v[i], tau);
    };
    int inliers = 0;
    for (const int i : alive) inliers += inlier(best_a, i);
    if (inliers < needed) break;
    for (int refit = 0; refit < 3; ++refit) {
      std::array<Vec3f, 3> m{};
      Vec3f rhs{};
      for (const int i : alive) {
        if (!inlier(best_a, i)) continue;
        const Vec3f& ray = r.rays[i];
        for (int row = 0; row < 3; ++row) {
          m[row] = m[row] + ray * ray[row];
        }
        rhs = rhs + ray * r.v[i];
      }
      Vec3f a;
      if (!region_math::solve(m[0], m[1], m[2], rhs, 0.0f, a)) break;
      best_a = a;
    }
    std::vector<int> rest;
    for (const int i : alive) {
      if (inlier(best_a, i))
        r.tag[i] = k;
      else
        rest.push_back(i);
    }
    r.planes.push_back(best_a);
    alive = std::move(rest);
  }
}

}  // namespace

FloatImage region_planes_cpu(const FloatImage& distance, const FloatImage& confidence,
                             const RegionPlaneParams& params, double min_distance,
                             double max_distance) {
  require_same_size("region planes",
                    {sized("distance", distance), sized("confidence", confidence)});
  if (!(min_distance > 0 && max_distance > min_distance))
    throw std::invalid_argument("region planes: the distance range must be 0 < min < max");
  params.check();
  const int w = distance.width(), h = distance.height();
  const float* d = distance.data();
  const float* c = confidence.data();
  FloatImage out(w, h);
  std::copy(d, d + distance.size(), out.data());
  if (w == 0 || h == 0) return out;
  const region_math::Rays rays(w, h);
  const float fill_below = float(params.fill_below), support = float(params.support);
  const int bsize = params.block;
  const int bw = (w + bsize - 1) / bsize, bh = (h + bsize - 1) / bsize, nb = bw * bh;

  // 1. Blocks (region_blocks.comp).
  std::vector<int> low(nb, 0), pick(nb, -1);
  for (int by = 0; by < bh; ++by) {
    for (int bx = 0; bx < bw; ++bx) {
      float best = -1.0f;
      for (int y = by * bsize; y < std::min(h, (by + 1) * bsize); ++y) {
        for (int x = bx * bsize; x < std::min(w, (bx + 1) * bsize); ++x) {
          const int i = y * w + x;
          if (!(d[i] > 0.0f)) continue;
          if (c[i] < fill_below) ++low[by * bw + bx];
          if (c[i] >= support && c[i] > best) {
            best = c[i];
            pick[by * bw + bx] = i;
          }
        }
      }
    }
  }

  // 2. Regions (region_merge.comp, region_flatten.comp, region_number.comp).
  std::vector<int> parent(nb);
  for (int b = 0; b < nb; ++b) parent[b] = b;
  for (int by = 0; by < bh; ++by) {
    for (int bx = 0; bx < bw; ++bx) {
      const int b = by * bw + bx;
      if (!low[b]) continue;
      const int left = by * bw + (bx + bw - 1) % bw;
      if (low[left]) unite(parent, b, left);
      if (by == 0) continue;
      for (int dx = -1; dx <= 1; ++dx) {
        const int j = (by - 1) * bw + (bx + dx + bw) % bw;
        if (low[j]) unite(parent, b, j);
      }
    }
  }
  // Each block straight at its root (region_flatten.comp).
  std::vector<long long> size(nb, 0);
  for (int b = 0; b < nb; ++b) {
    if (!low[b]) continue;
    parent[b] = find(parent, b);
    size[parent[b]] += low[b];
  }
  std::vector<int> slot(nb, -1);
  std::vector<Region> regions;
  for (int b = 0; b < nb && int(regions.size()) < params.max_regions; ++b) {
    if (low[b] && parent[b] == b && size[b] >= params.min_pixels) {
      slot[b] = int(regions.size());
      regions.push_back({});
      regions.back().root = b;
    }
  }
  if (regions.empty()) return out;
  auto region_of = [&](int b) { return low[b] ? slot[parent[b]] : -1; };

  // 3. Support (region_support.comp, region_threshold.comp, region_sample.comp).
  auto near_regions = [&](int b, std::array<int, region_math::kNearRegions>& list) {
    int count = 0;
    const int bx = b % bw, by = b / bw;
    for (int dy = -params.rim; dy <= params.rim; ++dy) {
      const int y = by + dy;
      if (y < 0 || y >= bh) continue;
      for (int dx = -params.rim; dx <= params.rim; ++dx) {
        if (dx * dx + dy * dy > params.rim * params.rim) continue;
        const int l = region_of(y * bw + ((bx + dx) % bw + bw) % bw);
        if (l < 0 || std::find(list.begin(), list.begin() + count, l) != list.begin() + count)
          continue;
        list[count++] = l;
        if (count == region_math::kNearRegions) return count;
      }
    }
    return count;
  };
  std::array<int, region_math::kNearRegions> list{};
  for (int b = 0; b < nb; ++b) {
    if (pick[b] < 0) continue;
    const int count = near_regions(b, list);
    for (int k = 0; k < count; ++k) {
      Region& r = regions[list[k]];
      const std::uint32_t key = region_math::support_hash(std::uint32_t(b), std::uint32_t(r.root));
      ++r.bins[key >> 24];
      r.candidates.push_back({key, std::uint32_t(b)});
    }
  }
  for (Region& r : regions) {
    r.supports = std::uint32_t(r.candidates.size());
    const int last = region_math::last_bin(r.bins, kRegionPlaneCandidates);
    std::erase_if(r.candidates, [&](const auto& e) { return int(e[0] >> 24) > last; });
    std::sort(r.candidates.begin(), r.candidates.end());
    r.candidates.resize(std::min<std::size_t>(r.candidates.size(), kRegionPlaneSample));
    for (const auto& e : r.candidates) {
      const int i = pick[e[1]];
      r.rays.push_back(rays(i % w, i / w));
      r.v.push_back(1.0f / d[i]);
    }
    // 4. Planes.
    find_planes(r, params);
  }

  // 5. Surround (region_surround.comp) and 6. the pixels (region_apply.comp).
  const float v_min = float(1.0 / max_distance), v_max = float(1.0 / min_distance);
  const float min_cos = region_math::surround_cos(params.surround_angle_deg);
  for (int b = 0; b < nb; ++b) {
    const int l = region_of(b);
    if (l < 0 || regions[l].planes.empty()) continue;
    const Region& r = regions[l];
    const int bx = b % bw, by = b / bw;
    const Vec3f centre =
        rays(std::min(w - 1, bx * bsize + bsize / 2), std::min(h - 1, by * bsize + bsize / 2));
    std::uint64_t quadrants = 0;
    for (std::size_t j = 0; j < r.rays.size(); ++j)
      if (r.tag[j] >= 0)
        quadrants |= std::uint64_t(region_math::quadrant(centre, r.rays[j], min_cos))
                     << (4 * r.tag[j]);
    const std::uint32_t mask = region_math::surrounding(quadrants);
    if (!mask) continue;
    for (int y = by * bsize; y < std::min(h, (by + 1) * bsize); ++y) {
      for (int x = bx * bsize; x < std::min(w, (bx + 1) * bsize); ++x) {
        const int i = y * w + x;
        if (!(d[i] > 0.0f) || !(c[i] < fill_below)) continue;
        float value;
        if (region_math::apply(r.planes.data(), int(r.planes.size()), mask, rays(x, y), d[i], c[i],
                               fill_below, v_min, v_max, value))
          out.data()[i] = value;
      }
    }
  }
  return out;
}

}  // namespace omnisweep::stitch
