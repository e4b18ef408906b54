#version 450
#extension GL_GOOGLE_include_directive : require
// Membrane fill, step 3 (server/stitch/membrane_fill.h, MembraneSolver::kMultigrid), in one
// workgroup, its phases apart by barriers (membrane_fill_cpu's steps, in float); phase 0:
//   1. the known cells' mean; an unknown cell is to fill when its component has min_cells cells,
//      else neither (its value the mean); the cells to fill start at the mean (no known cell:
//      nothing is filled);
//   2. the coarser levels' kinds: to fill when the four children are, else known when a child
//      takes part, else neither;
// then per cycle, phases 1 and 2:
//   3. a V-cycle: (1) down the levels, `sweeps` zebra line sweeps and the residual summed into the
//      coarser level (its corrections 0), coarsest_sweeps on the coarsest; (2) up the levels,
//      each correction added to its children to fill and `sweeps` more. In a line sweep one
//      invocation solves one row's runs of cells to fill (Thomas, Sherman-Morrison where the
//      whole row is to fill) in `scratch`.
layout(local_size_x_id = 100, local_size_y_id = 101, local_size_z_id = 102) in;

layout(std430, set = 0, binding = 0) coherent buffer Value { float value[]; };
layout(std430, set = 0, binding = 1) coherent buffer Rhs { float rhs[]; };
layout(std430, set = 0, binding = 2) coherent buffer Kind { uint kind[]; };
layout(std430, set = 0, binding = 3) readonly buffer Parent { uint parent[]; };
layout(std430, set = 0, binding = 4) readonly buffer Sizes { uint sizes[]; };
layout(std430, set = 0, binding = 5) coherent buffer Scratch { float scratch[]; };
#include "membrane_fill.glsl"

const float kPi = 3.14159265358979;
const int kThreads = 1024;  // the workgroup (MembraneFill's layout)
shared float partial_sum[kThreads];
shared uint partial_count[kThreads];

void sync() {
  memoryBarrierBuffer();
  barrier();
}

int level_w(int l) { return push.w >> l; }
int level_h(int l) { return push.h >> l; }
// The cells of the finer levels, a quarter fewer each: sum over m < l of w h / 4^m, in closed
// form (no loop: see MembraneFill::record on lavapipe's loop limit).
int level_base(int l) {
  const int cells = push.w * push.h;
  return (4 * cells - 4 * (cells >> (2 * l))) / 3;
}

// The stencil's weights of row i of h rows (membrane_fill.cc's RowWeights).
struct RowWeights {
  float north, south, azimuthal, own;
};
RowWeights row_weights(int i, int h) {
  const float step = kPi / float(h);
  const float s = sin((float(i) + 0.5) * step);
  return RowWeights(sin(float(i) * step), sin(float(i + 1) * step), 1.0 / s,
                    -2.0 * step * step * s);
}

// Neighbour q (an index into the level, base `base`) of weight `weight` added to (own, sum) where
// it takes part: its weight into the stencil's own, its weighted value into the sum.
vec2 neighbour(int base, int q, float weight, vec2 own_sum) {
  const uint kq = kind[base + q];
  return kq == kNeither ? own_sum : own_sum + vec2(weight, weight * value[base + q]);
}

// (own, the neighbours' weighted sum) of cell (i, j)'s equation at level l.
vec2 stencil(int l, int i, int j) {
  const int w = level_w(l), h = level_h(l), base = level_base(l);
  const RowWeights r = row_weights(i, h);
  vec2 own_sum = vec2(r.own, 0.0);
  own_sum = neighbour(base, i * w + (j + 1) % w, r.azimuthal, own_sum);
  own_sum = neighbour(base, i * w + (j + w - 1) % w, r.azimuthal, own_sum);
  if (i > 0) own_sum = neighbour(base, (i - 1) * w + j, r.north, own_sum);
  if (i + 1 < h) own_sum = neighbour(base, (i + 1) * w + j, r.south, own_sum);
  return own_sum;
}

// The residual f - A v of cell (i, j) at level l (an index k into the level).
float residual(int l, int i, int j) {
  const int k = level_base(l) + i * level_w(l) + j;
  const vec2 own_sum = stencil(l, i, j);
  return rhs[k] + own_sum.y - own_sum.x * value[k];
}

// Row i of level l: each run of cells to fill solved exactly given the rows beside it, for the
// change of its values from their residuals (so float's rounding falls on the change: by the
// poles a whole row's system is nearly singular, its lowest mode 1e-4 of its diagonal). Thomas's
// elimination streams over the row once forward and once back, each loop of exactly w steps
// whatever the runs (lavapipe's loop limit counts a SIMD group's iterations, and rows whose runs
// differ would multiply nested loops); a whole row to fill is a cycle, its corners moved into
// u v^T (Sherman-Morrison, membrane_fill.cc's solve_row). scratch: b', d' then x, u, a fine grid
// each.
void solve_row(int l, int i) {
  const int w = level_w(l), base = level_base(l), row = i * w;
  const int cells = push.w * push.h;
  const float a = -row_weights(i, level_h(l)).azimuthal;
  int first = -1;
  for (int j = 0; j < w; ++j) {
    if (first < 0 && kind[base + row + j] != kFill) first = j;
  }
  const bool cycle = first < 0;
  const int start = cycle ? 0 : first;
  float g = 1.0, b_prev = 1.0, d_prev = 0.0, u_prev = 0.0;
  bool in_run = false;
  for (int s = 0; s < w; ++s) {
    const int j = (start + s) % w;
    if (kind[base + row + j] != kFill) {
      in_run = false;
      continue;
    }
    float b = stencil(l, i, j).x, d = residual(l, i, j), u = 0.0;
    if (cycle && s == 0) {
      g = -b;
      b -= g;
      u = g;
    }
    if (cycle && s == w - 1) {
      b -= a * a / g;
      u = a;
    }
    if (in_run) {
      const float m = a / b_prev;
      b -= m * a;
      d -= m * d_prev;
      u -= m * u_prev;
    }
    scratch[row + s] = b;
    scratch[cells + row + s] = d;
    scratch[2 * cells + row + s] = u;
    b_prev = b;
    d_prev = d;
    u_prev = u;
    in_run = true;
  }
  float x_next = 0.0, v_next = 0.0;
  bool next_in_run = false;
  for (int s = w - 1; s >= 0; --s) {
    if (kind[base + row + (start + s) % w] != kFill) {
      next_in_run = false;
      continue;
    }
    const float b = scratch[row + s];
    const float x = (scratch[cells + row + s] - (next_in_run ? a * x_next : 0.0)) / b;
    const float v = (scratch[2 * cells + row + s] - (next_in_run ? a * v_next : 0.0)) / b;
    scratch[cells + row + s] = x;
    scratch[2 * cells + row + s] = v;
    x_next = x;
    v_next = v;
    next_in_run = true;
  }
  float factor = 0.0;
  if (cycle) {
    factor = (scratch[cells + row] + a / g * scratch[cells + row + w - 1]) /
             (1.0 + scratch[2 * cells + row] + a / g * scratch[2 * cells + row + w - 1]);
  }
  for (int s = 0; s < w; ++s) {
    const int k = base + row + (start + s) % w;
    if (kind[k] == kFill) value[k] += scratch[cells + row + s] - factor * scratch[2 * cells + row + s];
  }
}

// `sweeps` zebra line sweeps over level l: the even rows, then the odd ones.
void relax(int l, int sweeps) {
  const int h = level_h(l);
  const int t = int(gl_LocalInvocationIndex);
  for (int it = 0; it < sweeps; ++it) {
    for (int colour = 0; colour < 2; ++colour) {
      for (int i = colour + 2 * t; i < h; i += 2 * kThreads) solve_row(l, i);
      sync();
    }
  }
}

// Phase 0: steps 1 and 2.
void setup() {
  const int t = int(gl_LocalInvocationIndex), size = kThreads;
  const int cells = push.w * push.h;
  // 1. The known cells' mean.
  float sum = 0.0;
  uint count = 0u;
  for (int k = t; k < cells; k += size) {
    if (kind[k] == kKnown) {
      sum += value[k];
      ++count;
    }
  }
  partial_sum[t] = sum;
  partial_count[t] = count;
  barrier();
  for (int stride = size / 2; stride > 0; stride /= 2) {
    if (t < stride) {
      partial_sum[t] += partial_sum[t + stride];
      partial_count[t] += partial_count[t + stride];
    }
    barrier();
  }
  const bool any = partial_count[0] > 0u;
  const float mean = any ? partial_sum[0] / float(partial_count[0]) : 0.0;
  for (int k = t; k < cells; k += size) {
    rhs[k] = 0.0;
    if (kind[k] != kUnknown) continue;
    const bool fill = any && sizes[parent[k]] >= uint(push.min_cells);
    kind[k] = fill ? kFill : kNeither;
    value[k] = mean;
  }
  sync();
  // 2. The coarser levels' kinds.
  for (int l = 1; l < push.levels; ++l) {
    const int w = level_w(l), fine_w = level_w(l - 1);
    const int base = level_base(l), fine = level_base(l - 1);
    for (int k = t; k < w * level_h(l); k += size) {
      const int i = k / w, j = k % w;
      int fills = 0, takes_part = 0;
      for (int q = 0; q < 4; ++q) {
        const uint kq = kind[fine + (2 * i + q / 2) * fine_w + 2 * j + q % 2];
        fills += kq == kFill ? 1 : 0;
        takes_part += kq != kNeither ? 1 : 0;
      }
      kind[base + k] = fills == 4 ? kFill : takes_part > 0 ? kKnown : kNeither;
    }
    sync();
  }
}

// Phase 1: the way down of a V-cycle, and the coarsest level.
void cycle_down() {
  const int t = int(gl_LocalInvocationIndex), size = kThreads;
  const int coarsest = push.levels - 1;
  for (int l = 0; l < coarsest; ++l) {
    relax(l, push.sweeps);
    const int w = level_w(l + 1), fine_w = level_w(l);
    const int base = level_base(l + 1), fine = level_base(l);
    for (int k = t; k < w * level_h(l + 1); k += size) {
      const int i = k / w, j = k % w;
      float f = 0.0;
      for (int q = 0; q < 4; ++q) {
        const int fi = 2 * i + q / 2, fj = 2 * j + q % 2;
        if (kind[fine + fi * fine_w + fj] == kFill) f += residual(l, fi, fj);
      }
      rhs[base + k] = f;
      value[base + k] = 0.0;
    }
    sync();
  }
  relax(coarsest, push.coarsest_sweeps);
}

// Phase 2: the way up of the V-cycle.
void cycle_up() {
  const int t = int(gl_LocalInvocationIndex), size = kThreads;
  const int coarsest = push.levels - 1;
  for (int l = coarsest - 1; l >= 0; --l) {
    const int w = level_w(l), coarse_w = level_w(l + 1);
    const int base = level_base(l), coarse = level_base(l + 1);
    for (int k = t; k < w * level_h(l); k += size) {
      if (kind[base + k] == kFill)
        value[base + k] += value[coarse + (k / w / 2) * coarse_w + (k % w) / 2];
    }
    sync();
    relax(l, push.sweeps);
  }
}

void main() {
  if (push.phase == 0)
    setup();
  else if (push.phase == 1)
    cycle_down();
  else
    cycle_up();
}
