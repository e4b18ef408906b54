#include "server/stitch/edge_check.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "server/stitch/same_size.h"
namespace omnisweep::stitch {
namespace {

struct EdgePush {
  std::uint32_t width, height;
  std::int32_t block, reach;
  float step, color, factor;
};

EdgePush push_for(int width, int height, const EdgeCheckParams& p) {
  return {std::uint32_t(width), std::uint32_t(height), p.block,        p.reach,
          float(p.step),        float(p.color),        float(p.factor)};
}

int blocks(int pixels, int block) { return (pixels + block - 1) / block; }

// edge_marks.comp's test at pixel (x, y), in float arithmetic as the kernel's.
bool carried(const Rgb8Image& rgb, const FloatImage& distance, const EdgePush& p, int x, int y) {
  const int w = int(p.width), h = int(p.height);
  float lo = 1e30f, hi = -1e30f;
  std::array<float, 3> clo{1e30f, 1e30f, 1e30f}, chi{-1e30f, -1e30f, -1e30f};
  for (int dy = -1; dy <= 1; ++dy) {
    const int yy = y + dy;
    if (yy < 0 || yy >= h) continue;
    for (int dx = -1; dx <= 1; ++dx) {
      const int xx = (x + dx + w) % w;
      const float d = distance(xx, yy);
      if (!(d > 0.0f)) continue;
      const float v = 1.0f / d;
      lo = std::min(lo, v);
      hi = std::max(hi, v);
      for (int c = 0; c < 3; ++c) {
        clo[c] = std::min(clo[c], float(rgb(xx, yy, c)));
        chi[c] = std::max(chi[c], float(rgb(xx, yy, c)));
      }
    }
  }
  const float range = std::max({chi[0] - clo[0], chi[1] - clo[1], chi[2] - clo[2]});
  return hi - lo > p.step && range < p.color;
}

}  // namespace

EdgeCheckParams EdgeCheckParams::for_width(int width) {
  EdgeCheckParams p;
  p.block = std::max(1, int(std::lround(p.block * width / 2048.0)));
  return p;
}

void EdgeCheckParams::check() const {
  if (block < 1 || reach < 0 || !(step > 0) || !(color > 0) || !(factor >= 0 && factor <= 1))
    throw std::invalid_argument(
        "edge check: needs block >= 1, reach >= 0, step > 0, color > 0 and factor in [0, 1]");
}

FloatImage edge_check_cpu(const Rgb8Image& rgb, const FloatImage& distance,
                          const FloatImage& confidence, const EdgeCheckParams& params) {
  params.check();
  const int w = distance.width(), h = distance.height();
  require_same_size("edge check", {sized("distance", distance), sized("colour", rgb),
                                   sized("confidence", confidence)});
  const EdgePush p = push_for(w, h, params);
  const int nx = blocks(w, p.block), ny = blocks(h, p.block);
  std::vector<char> marks(std::size_t(nx) * ny, 0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      if (distance(x, y) > 0.0f && carried(rgb, distance, p, x, y))
        marks[std::size_t(y / p.block) * nx + x / p.block] = 1;
  // Per block, whether a marked block lies within reach (edge_check.comp asks it per pixel).
  std::vector<char> near(marks.size(), 0);
  for (int by = 0; by < ny; ++by)
    for (int bx = 0; bx < nx; ++bx)
      for (int yy = std::max(0, by - p.reach); yy <= std::min(ny - 1, by + p.reach); ++yy)
        for (int dx = -p.reach; dx <= p.reach; ++dx)
          near[std::size_t(by) * nx + bx] |=
              marks[std::size_t(yy) * nx + ((bx + dx) % nx + nx) % nx];
  FloatImage out = confidence.clone();
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      if (near[std::size_t(y / p.block) * nx + x / p.block]) out(x, y) *= p.factor;
  return out;
}

EdgeCheck::EdgeCheck(gpu::Context& context, int width, int height, const EdgeCheckParams& params)
    : width_(width),
      height_(height),
      params_(params),
      marks_(context,
             std::uint64_t(blocks(width, params.block)) * blocks(height, params.block) * 4),
      marks_kernel_(context, gpu::Shader::kEdgeMarks,
                    {.bindings = {1, 1, 1}, .push_constant_bytes = sizeof(EdgePush)}),
      apply_(context, gpu::Shader::kEdgeCheck,
             {.bindings = {1, 1}, .push_constant_bytes = sizeof(EdgePush)}) {
  params.check();
}

void EdgeCheck::record(gpu::Sequence& seq, const gpu::Buffer& color, const gpu::Buffer& distance,
                       gpu::Buffer& confidence) const {
  const std::uint64_t bytes = std::uint64_t(width_) * height_ * 4;
  if (color.size() < bytes || distance.size() < bytes || confidence.size() < bytes)
    throw std::invalid_argument("edge check: the panorama buffers are smaller than its size");
  const EdgePush push = push_for(width_, height_, params_);
  seq.dispatch(marks_kernel_, {color, distance, marks_}, push,
               marks_kernel_.groups_for(std::uint32_t(blocks(width_, params_.block)),
                                        std::uint32_t(blocks(height_, params_.block))));
  seq.barrier();
  seq.dispatch(apply_, {marks_, confidence}, push,
               apply_.groups_for(std::uint32_t(width_), std::uint32_t(height_)));
}

}  // namespace omnisweep::stitch
