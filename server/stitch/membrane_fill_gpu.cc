// MembraneFill: the membrane fill on the GPU (membrane_fill.h), the membrane_*.comp kernels.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "omnisweep/gpu/shaders.h"
#include "server/stitch/membrane_fill.h"

namespace omnisweep::stitch {
namespace {

// membrane_fill.glsl's push constants.
struct MembranePush {
  std::uint32_t width, height;
  std::int32_t cell, w, h, levels, min_cells, min_count, cycles, sweeps, coarsest_sweeps;
  float known_from, fill_below, inv_d_min, inv_d_max;
  std::int32_t phase;
};

gpu::KernelLayout layout(std::uint32_t buffers, std::array<std::uint32_t, 3> local) {
  return gpu::KernelLayout::storage_buffers(buffers, sizeof(MembranePush), local);
}

constexpr std::array<std::uint32_t, 3> kPerCell = {8, 8, 1};
constexpr std::uint32_t kSolveThreads = 1024;  // membrane_solve.comp's kThreads

// The fine grid's cells, checked as membrane_fill_cpu checks them.
int cells_across(int width, int height, const MembraneFillParams& params) {
  params.check();
  params.check_panorama(width, height);
  if (width < 1) throw std::invalid_argument("membrane fill: the panorama is empty");
  if (params.solver != MembraneSolver::kMultigrid)
    throw std::invalid_argument("membrane fill: the GPU solves by multigrid only");
  return width / params.cell;
}

// The multigrid's levels: halved while the grid has more than 8 rows, an even number.
int level_count(int h) {
  int levels = 1;
  for (; h > 8 && h % 2 == 0; h /= 2) ++levels;
  return levels;
}

std::uint64_t level_cells(int w, int h, int levels) {
  std::uint64_t total = 0;
  for (int l = 0; l < levels; ++l) total += std::uint64_t(w >> l) * std::uint64_t(h >> l);
  return total;
}

}  // namespace

MembraneFill::MembraneFill(gpu::Context& context, int width, int height,
                           const MembraneFillParams& params, double min_distance,
                           double max_distance)
    : width_(width),
      height_(height),
      params_(params),
      min_distance_(min_distance),
      max_distance_(max_distance),
      w_(cells_across(width, height, params)),
      h_(w_ / 2),
      levels_(level_count(h_)),
      value_(context, 4 * level_cells(w_, h_, levels_)),
      rhs_(context, 4 * level_cells(w_, h_, levels_)),
      kind_(context, 4 * level_cells(w_, h_, levels_)),
      parent_(context, 4 * std::uint64_t(w_) * std::uint64_t(h_)),
      sizes_(context, 4 * std::uint64_t(w_) * std::uint64_t(h_)),
      scratch_(context, std::uint64_t(12) * std::uint64_t(w_) * std::uint64_t(h_)),
      cells_(context, gpu::Shader::kMembraneCells, layout(6, kPerCell)),
      merge_(context, gpu::Shader::kMembraneMerge, layout(1, kPerCell)),
      flatten_(context, gpu::Shader::kMembraneFlatten, layout(2, kPerCell)),
      solve_(context, gpu::Shader::kMembraneSolve, layout(6, {kSolveThreads, 1, 1})),
      apply_(context, gpu::Shader::kMembraneApply, layout(4, {16, 16, 1})) {
  if (!(min_distance > 0 && max_distance > min_distance))
    throw std::invalid_argument("membrane fill: the distance range must be 0 < min < max");
}

void MembraneFill::record(gpu::Sequence& seq, gpu::Buffer& distance,
                          const gpu::Buffer& confidence) const {
  const std::uint64_t bytes = std::uint64_t(width_) * std::uint64_t(height_) * 4;
  if (distance.size() < bytes || confidence.size() < bytes)
    throw std::invalid_argument("membrane fill: the panorama buffers are smaller than its size");
  const MembraneFillParams& p = params_;
  const double c2 = double(p.cell) * p.cell;
  MembranePush push{std::uint32_t(width_),
                    std::uint32_t(height_),
                    p.cell,
                    w_,
                    h_,
                    levels_,
                    p.min_cells,
                    std::max(1, int(std::ceil(p.known_share * c2))),
                    p.cycles,
                    p.sweeps,
                    p.coarsest_sweeps,
                    float(p.known_from),
                    float(p.fill_below),
                    float(1.0 / min_distance_),
                    float(1.0 / max_distance_),
                    0};
  const auto per_cell = cells_.groups_for(std::uint32_t(w_), std::uint32_t(h_));
  seq.dispatch(cells_, {distance, confidence, value_, kind_, parent_, sizes_}, push, per_cell);
  seq.barrier();
  seq.dispatch(merge_, {parent_}, push, per_cell);
  seq.barrier();
  seq.dispatch(flatten_, {parent_, sizes_}, push, per_cell);
  seq.barrier();
  // The kinds, then two dispatches per V-cycle (down, up): lavapipe ends every loop of an
  // invocation (a SIMD group of 8) once it has run 65 535 iterations of its loops in all, and a
  // whole cycle at 256 x 128 cells runs about 60 000 (the line solves stream over their rows in
  // loops of the row's width for that reason, membrane_solve.comp).
  for (int phase = 0; phase <= 2 * p.cycles; ++phase) {
    push.phase = phase == 0 ? 0 : 2 - phase % 2;
    seq.dispatch(solve_, {value_, rhs_, kind_, parent_, sizes_, scratch_}, push, {1, 1, 1});
    seq.barrier();
  }
  seq.dispatch(apply_, {distance, confidence, value_, kind_}, push,
               apply_.groups_for(std::uint32_t(width_), std::uint32_t(height_)));
}

}  // namespace omnisweep::stitch
