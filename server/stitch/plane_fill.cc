#include "server/stitch/plane_fill.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "server/stitch/panorama_rays.h"
#include "server/stitch/same_size.h"

namespace omnisweep::stitch {
namespace {

struct FillPush {
  std::uint32_t width, height;
  std::int32_t step, taps;
  float fill_below, support, sigma_c, lambda, inv_d_min, inv_d_max;
  std::int32_t refits;
  float tau;
};

FillPush push_for(int width, int height, double fill_below, double min_distance,
                  double max_distance) {
  const PlaneFillParams p = PlaneFillParams::for_width(width);
  return {std::uint32_t(width),
          std::uint32_t(height),
          p.step,
          p.taps,
          float(fill_below),
          float(std::max(p.support, fill_below)),
          float(p.sigma_c),
          float(p.lambda),
          float(1.0 / min_distance),
          float(1.0 / max_distance),
          p.refits,
          float(p.tau)};
}

// plane_fill.comp's table: per column (cos, sin) of the longitude, per row (sin, cos) of the
// colatitude, then (spatial weight, 0) per tap offset -taps .. taps.
std::vector<float> ray_table(int width, int height) {
  const PlaneFillParams p = PlaneFillParams::for_width(width);
  std::vector<float> table = panorama_ray_table(width, height);
  for (int t = -p.taps; t <= p.taps; ++t) {
    const double s = double(t) * p.step;
    table.insert(table.end(), {float(std::exp(-s * s / (2 * p.sigma_s * p.sigma_s))), 0.0f});
  }
  return table;
}

// The table on the GPU, computed once.
gpu::Buffer table_buffer(gpu::Context& context, int width, int height) {
  const std::vector<float> table = ray_table(width, height);
  gpu::Buffer buffer(context, table.size() * 4);
  buffer.upload(std::span<const float>(table));
  return buffer;
}

using Ray = std::array<float, 3>;

Ray ray(const FillPush& p, const float* table, int x, int y) {
  const float* longitude = table + 2 * std::size_t(x);
  const float* colatitude = table + 2 * (std::size_t(p.width) + y);
  return {colatitude[0] * longitude[0], colatitude[0] * longitude[1], colatitude[1]};
}

float spatial(const FillPush& p, const float* table, int t) {
  return table[2 * (std::size_t(p.width) + p.height + t + p.taps)];
}

constexpr int kCell = 4;

bool to_fill(const FillPush& p, const float* distance, const float* confidence, std::size_t i) {
  return distance[i] > 0.0f && confidence[i] < p.fill_below;
}

// The weighted least-squares plane around (x0, y0) (its ray r0) for the colour ci into s; with
// `robust`, each tap's weight also falls with its distance from `prior`'s plane (plane_fit.comp's
// fit, step for step). False where there is no support or the system is singular.
bool fit(const FillPush& p, const float* table, const float* distance, const float* confidence,
         const std::uint8_t* rgb, const float* ci, int x0, int y0, const Ray& r0,
         const std::array<float, 4>& prior, bool robust, std::array<float, 4>& s) {
  const int w = int(p.width), h = int(p.height);
  float m[4][4] = {}, rhs[4] = {}, wsum = 0.0f;  // m[c][r], as the kernel's mat4
  const float colour_scale = 1.0f / (2.0f * p.sigma_c * p.sigma_c);
  const float residual_scale = robust ? 1.0f / (2.0f * p.tau * p.tau) : 0.0f;
  for (int ty = -p.taps; ty <= p.taps; ++ty) {
    const int y = y0 + ty * p.step;
    if (y < 0 || y >= h) continue;
    const float wy = spatial(p, table, ty);
    for (int tx = -p.taps; tx <= p.taps; ++tx) {
      int x = x0 + tx * p.step;
      x = x < 0 ? x + w : (x >= w ? x - w : x);
      const std::size_t j = std::size_t(y) * w + x;
      const float dj = distance[j], cj = confidence[j];
      if (!(dj > 0.0f) || cj < p.support) continue;
      float dc2 = 0.0f;
      for (int c = 0; c < 3; ++c) {
        const float dc = ci[c] - float(rgb[3 * j + c]);
        dc2 += dc * dc;
      }
      const Ray rj = ray(p, table, x, y);
      const float u[4] = {rj[0] - r0[0], rj[1] - r0[1], rj[2] - r0[2], 1.0f};
      const float res =
          1.0f / dj - (prior[0] * u[0] + prior[1] * u[1] + prior[2] * u[2] + prior[3] * u[3]);
      const float wt = cj * std::exp(-dc2 * colour_scale - res * res * residual_scale) *
                       (wy * spatial(p, table, tx));
      float wu[4];
      for (int k = 0; k < 4; ++k) wu[k] = wt * u[k];
      for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) m[c][r] += u[r] * wu[c];
      for (int r = 0; r < 4; ++r) rhs[r] += wu[r] * (1.0f / dj);
      wsum += wt;
    }
  }
  if (!(wsum > 1e-6f)) return false;
  for (int r = 0; r < 3; ++r) m[r][r] += p.lambda * wsum;
  float l[4][4] = {}, z[4] = {};  // l[c][r]: L's row r, column c
  s = {};
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c <= r; ++c) {
      float t = m[c][r];
      for (int k = 0; k < c; ++k) t -= l[k][r] * l[k][c];
      if (c == r) {
        if (!(t > 0.0f)) return false;
        l[r][r] = std::sqrt(t);
      } else {
        l[c][r] = t / l[c][c];
      }
    }
    float t = rhs[r];
    for (int k = 0; k < r; ++k) t -= l[k][r] * z[k];
    z[r] = t / l[r][r];
  }
  for (int r = 3; r >= 0; --r) {
    float t = z[r];
    for (int k = r + 1; k < 4; ++k) t -= l[r][k] * s[k];
    s[r] = t / l[r][r];
  }
  return s[3] > 0.0f && !std::isinf(s[3]);
}

// The plane of the cell of kCell x kCell pixels from (x0, y0): (a, b), b = 0 for none
// (plane_fit.comp's main, step for step).
std::array<float, 4> fit_cell(const FillPush& p, const float* table, const float* distance,
                              const float* confidence, const std::uint8_t* rgb, int x0, int y0) {
  const int w = int(p.width), h = int(p.height);
  float colour_sum[3] = {};
  int targets = 0;
  for (int y = y0; y < std::min(y0 + kCell, h); ++y) {
    for (int x = x0; x < std::min(x0 + kCell, w); ++x) {
      const std::size_t i = std::size_t(y) * w + x;
      if (!to_fill(p, distance, confidence, i)) continue;
      for (int c = 0; c < 3; ++c) colour_sum[c] += float(rgb[3 * i + c]);
      ++targets;
    }
  }
  constexpr std::array<float, 4> kNone = {0.0f, 0.0f, 0.0f, 0.0f};
  if (targets == 0) return kNone;
  float ci[3];
  for (int c = 0; c < 3; ++c) ci[c] = colour_sum[c] / float(targets);
  const Ray r0 = ray(p, table, x0, y0);
  std::array<float, 4> s;
  if (!fit(p, table, distance, confidence, rgb, ci, x0, y0, r0, kNone, false, s)) return kNone;
  for (int k = 0; k < p.refits; ++k) {
    std::array<float, 4> next;
    if (!fit(p, table, distance, confidence, rgb, ci, x0, y0, r0, s, true, next)) break;
    s = next;
  }
  return s;
}

// Pixel (x, y) from the cells' planes (plane_fill.comp's main, step for step).
float fill_pixel(const FillPush& p, const float* table, const float* distance,
                 const float* confidence, const std::vector<std::array<float, 4>>& planes, int x,
                 int y) {
  const int w = int(p.width), h = int(p.height);
  const std::size_t i = std::size_t(y) * w + x;
  const float d = distance[i];
  if (!to_fill(p, distance, confidence, i)) return d;
  const int cells_x = (w + kCell - 1) / kCell, cells_y = (h + kCell - 1) / kCell;
  const float fx = (float(x) - 0.5f * float(kCell - 1)) / float(kCell);
  const float fy = (float(y) - 0.5f * float(kCell - 1)) / float(kCell);
  const int c0x = int(std::floor(fx)), c0y = int(std::floor(fy));
  const float tx = fx - float(c0x), ty = fy - float(c0y);
  const Ray rp = ray(p, table, x, y);
  float v = 0.0f, wsum = 0.0f;
  for (int dy = 0; dy < 2; ++dy) {
    const int cy = std::clamp(c0y + dy, 0, cells_y - 1);
    const float wy = dy == 0 ? 1.0f - ty : ty;
    for (int dx = 0; dx < 2; ++dx) {
      int cx = c0x + dx;
      cx = cx < 0 ? cx + cells_x : (cx >= cells_x ? cx - cells_x : cx);
      const float weight = wy * (dx == 0 ? 1.0f - tx : tx);
      const std::array<float, 4>& s = planes[std::size_t(cy) * cells_x + cx];
      if (!(s[3] > 0.0f) || !(weight > 0.0f)) continue;
      const Ray r0 = ray(p, table, cx * kCell, cy * kCell);
      v += weight *
           (s[3] + (s[0] * (rp[0] - r0[0]) + s[1] * (rp[1] - r0[1]) + s[2] * (rp[2] - r0[2])));
      wsum += weight;
    }
  }
  if (!(wsum > 0.0f)) return d;
  const float alpha = 1.0f - confidence[i] / p.fill_below;
  v = alpha * (v / wsum) + (1.0f - alpha) * (1.0f / d);
  if (!(v > 0.0f) || std::isinf(v)) return d;
  return 1.0f / std::clamp(v, p.inv_d_max, p.inv_d_min);
}

}  // namespace

PlaneFillParams PlaneFillParams::for_width(int width) {
  PlaneFillParams p;
  const double scale = double(width) / 2048.0;
  p.step = std::max(1, int(std::lround(p.step * scale)));
  p.sigma_s = 4.0 * p.step;
  return p;
}

FloatImage plane_fill_cpu(const Rgb8Image& rgb, const FloatImage& distance,
                          const FloatImage& confidence, double fill_below, double min_distance,
                          double max_distance) {
  require_same_size("plane fill", {sized("distance", distance), sized("colour", rgb),
                                   sized("confidence", confidence)});
  const FillPush p =
      push_for(distance.width(), distance.height(), fill_below, min_distance, max_distance);
  const std::vector<float> table = ray_table(distance.width(), distance.height());
  const int w = distance.width(), h = distance.height();
  std::vector<std::array<float, 4>> planes;
  for (int y = 0; y < h; y += kCell)
    for (int x = 0; x < w; x += kCell)
      planes.push_back(
          fit_cell(p, table.data(), distance.data(), confidence.data(), rgb.data(), x, y));
  FloatImage out(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      out.data()[std::size_t(y) * w + x] =
          fill_pixel(p, table.data(), distance.data(), confidence.data(), planes, x, y);
  return out;
}

PlaneFill::PlaneFill(gpu::Context& context, int width, int height, double fill_below,
                     double min_distance, double max_distance)
    : width_(width),
      height_(height),
      fill_below_(fill_below),
      min_distance_(min_distance),
      max_distance_(max_distance),
      table_(table_buffer(context, width, height)),
      planes_(context,
              std::uint64_t((width + kCell - 1) / kCell) * ((height + kCell - 1) / kCell) * 16),
      fit_(context, gpu::Shader::kPlaneFit,
           {.bindings = {1, 1, 1, 1, 1}, .push_constant_bytes = sizeof(FillPush)}),
      fill_(context, gpu::Shader::kPlaneFill,
            {.bindings = {1, 1, 1, 1, 1}, .push_constant_bytes = sizeof(FillPush)}) {}

void PlaneFill::record(gpu::Sequence& seq, const gpu::Buffer& color, const gpu::Buffer& distance,
                       const gpu::Buffer& confidence, gpu::Buffer& out) const {
  const std::uint64_t bytes = std::uint64_t(width_) * height_ * 4;
  if (color.size() < bytes || distance.size() < bytes || confidence.size() < bytes ||
      out.size() < bytes)
    throw std::invalid_argument("plane fill: the panorama buffers are smaller than its size");
  const FillPush push = push_for(width_, height_, fill_below_, min_distance_, max_distance_);
  seq.dispatch(fit_, {color, distance, confidence, table_, planes_}, push,
               fit_.groups_for(std::uint32_t((width_ + kCell - 1) / kCell),
                               std::uint32_t((height_ + kCell - 1) / kCell)));
  seq.barrier();
  seq.dispatch(fill_, {distance, confidence, table_, planes_, out}, push,
               fill_.groups_for(std::uint32_t(width_), std::uint32_t(height_)));
}

}  // namespace omnisweep::stitch
