#include "server/stitch/membrane_fill.h"

#include <Eigen/Sparse>
#include <Eigen/SparseLU>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "server/stitch/same_size.h"

namespace omnisweep::stitch {

MembraneFillParams MembraneFillParams::for_width(int width) {
  MembraneFillParams p;
  p.cell = std::max(1, int(std::lround(p.cell * double(width) / 2048.0)));
  return p;
}

void MembraneFillParams::check_panorama(int width, int height) const {
  if (width != 2 * height || width % cell != 0 || height % cell != 0) {
    throw std::invalid_argument(
        "membrane fill: the panorama is " + std::to_string(width) + "x" + std::to_string(height) +
        "; it must be 2:1 and a whole number of cells of " + std::to_string(cell) + " pixels");
  }
}

void MembraneFillParams::check() const {
  auto bad = [](const char* name, double value, const std::string& range) {
    throw std::invalid_argument("MembraneFillParams::" + std::string(name) + " is " +
                                std::to_string(value) + "; it must be " + range);
  };
  if (!(fill_below > 0 && fill_below <= 1)) bad("fill_below", fill_below, "in (0, 1]");
  if (!(known_from >= 0 && known_from <= 1)) bad("known_from", known_from, "in [0, 1]");
  if (!(known_share > 0 && known_share <= 1)) bad("known_share", known_share, "in (0, 1]");
  if (cell < 1 || cell > 64) bad("cell", cell, "in [1, 64]");
  if (min_cells < 1) bad("min_cells", min_cells, "at least 1");
  if (cycles < 1 || cycles > 100) bad("cycles", cycles, "in [1, 100]");
  if (sweeps < 1 || sweeps > 100) bad("sweeps", sweeps, "in [1, 100]");
  if (coarsest_sweeps < 1 || coarsest_sweeps > 10000)
    bad("coarsest_sweeps", coarsest_sweeps, "in [1, 10000]");
}

namespace {

// The unknown cells' 4-connected components (wrapping left to right): each cell's component,
// -1 for a known cell, and each component's size.
std::vector<int> components(const std::vector<char>& known, int w, int h, std::vector<int>& sizes) {
  std::vector<int> label(known.size(), -1);
  std::vector<int> stack;
  for (std::size_t seed = 0; seed < known.size(); ++seed) {
    if (known[seed] || label[seed] >= 0) continue;
    const int id = int(sizes.size());
    sizes.push_back(0);
    label[seed] = id;
    stack.assign(1, int(seed));
    while (!stack.empty()) {
      const int k = stack.back();
      stack.pop_back();
      ++sizes[std::size_t(id)];
      const int i = k / w, j = k % w;
      const int next[4] = {i > 0 ? k - w : -1, i + 1 < h ? k + w : -1, i * w + (j + 1) % w,
                           i * w + (j + w - 1) % w};
      for (const int q : next) {
        if (q < 0 || known[std::size_t(q)] || label[std::size_t(q)] >= 0) continue;
        label[std::size_t(q)] = id;
        stack.push_back(q);
      }
    }
  }
  return label;
}

// A cell's part in the solve.
enum Kind : char { kNeither = 0, kKnown = 1, kFill = 2 };

// The stencil's weights of row i of h rows, times sin(theta_i) step^2: north and south (the
// polar flux at the row's edges), each azimuthal neighbour's, and the +2 term's (negative).
struct RowWeights {
  double north, south, azimuthal, own;
};
RowWeights row_weights(int i, int h) {
  const double step = std::numbers::pi / h;
  const double s = std::sin((i + 0.5) * step);
  return {std::sin(i * step), std::sin((i + 1) * step), 1.0 / s, -2.0 * step * step * s};
}

// Calls visit(q, weight) for the stencil's neighbours of cell (i, j) of a w x h grid: east and
// west (wrapping), north and south where they exist.
template <typename Visit>
void for_neighbours(int i, int j, int w, int h, const RowWeights& r, Visit&& visit) {
  const auto row = std::size_t(i) * std::size_t(w);
  visit(row + std::size_t((j + 1) % w), r.azimuthal);
  visit(row + std::size_t((j + w - 1) % w), r.azimuthal);
  if (i > 0) visit(row - std::size_t(w) + std::size_t(j), r.north);
  if (i + 1 < h) visit(row + std::size_t(w) + std::size_t(j), r.south);
}

// Solves the fill cells directly (kDirect); false where the system is singular.
bool solve_direct(std::vector<double>& v, const std::vector<char>& kind, int w, int h) {
  const auto cells = kind.size();
  std::vector<int> unknown_index(cells, -1);
  int unknowns = 0;
  for (std::size_t k = 0; k < cells; ++k) {
    if (kind[k] == kFill) unknown_index[k] = unknowns++;
  }
  if (unknowns == 0) return true;
  std::vector<Eigen::Triplet<double>> entries;
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(unknowns);
  const auto ww = std::size_t(w);
  for (std::size_t k = 0; k < cells; ++k) {
    const int row = unknown_index[k];
    if (row < 0) continue;
    const std::size_t i = k / ww, j = k % ww;
    const RowWeights r = row_weights(int(i), h);
    double own = r.own;
    const auto couple = [&](std::size_t q, double weight) {
      own += weight;  // a fill cell's neighbours are fill or known: the components are maximal
      if (unknown_index[q] >= 0)
        entries.emplace_back(row, unknown_index[q], -weight);
      else
        rhs[row] += weight * v[q];
    };
    for_neighbours(int(i), int(j), w, h, r, couple);
    entries.emplace_back(row, row, own);
  }
  Eigen::SparseMatrix<double> system(unknowns, unknowns);
  system.setFromTriplets(entries.begin(), entries.end());
  Eigen::SparseLU<Eigen::SparseMatrix<double>> solver;
  solver.compute(system);
  if (solver.info() != Eigen::Success) return false;
  const Eigen::VectorXd solution = solver.solve(rhs);
  for (std::size_t k = 0; k < cells; ++k) {
    if (unknown_index[k] >= 0) v[k] = solution[unknown_index[k]];
  }
  return true;
}

// One level of the multigrid's pyramid: its cells' values (the fine level: the field; coarser:
// corrections) and right-hand side.
struct Level {
  int w, h;
  std::vector<double> v;
  std::vector<char> kind;
  std::vector<double> f{};  // empty: 0 (the fine level)
};

// Cell (i, j) of a level's grid.
std::size_t at(const Level& l, int i, int j) {
  return std::size_t(i) * std::size_t(l.w) + std::size_t(j);
}

// Cell (i, j)'s equation at a level, row weights r: its own weight (the stencil's neighbours that
// take part; a neighbour that is neither is left out) and its residual f - A v.
struct Equation {
  double own, residual;
};
Equation equation(const Level& l, int i, int j, const RowWeights& r) {
  double own = r.own, sum = 0;
  for_neighbours(i, j, l.w, l.h, r, [&](std::size_t q, double weight) {
    if (l.kind[q] == kNeither) return;
    own += weight;
    sum += weight * l.v[q];
  });
  const std::size_t k = at(l, i, j);
  return {own, (l.f.empty() ? 0.0 : l.f[k]) + sum - own * l.v[k]};
}

// Solves the tridiagonal system a x_{k-1} + b_k x_k + a x_{k+1} = d_k (k = 0..n-1), cyclic when
// `cyclic` (x_{-1} = x_{n-1}, x_n = x_0), in place of d (Thomas; Sherman-Morrison for the cycle).
void solve_row(std::vector<double>& b, std::vector<double>& d, double a, bool cyclic) {
  const auto n = b.size();
  const auto thomas = [a, n](std::vector<double> bb, std::vector<double>& dd) {
    for (std::size_t k = 1; k < n; ++k) {
      const double m = a / bb[k - 1];
      bb[k] -= m * a;
      dd[k] -= m * dd[k - 1];
    }
    dd[n - 1] /= bb[n - 1];
    for (std::size_t k = n - 1; k-- > 0;) dd[k] = (dd[k] - a * dd[k + 1]) / bb[k];
  };
  if (!cyclic || n < 3) {
    thomas(b, d);
    return;
  }
  // A = T + u v^T with u = (g, 0.., a), v = (1, 0.., a / g): T's corners adjusted.
  const double g = -b[0];
  std::vector<double> bt = b;
  bt[0] -= g;
  bt[n - 1] -= a * a / g;
  std::vector<double> u(n, 0.0);
  u[0] = g;
  u[n - 1] = a;
  thomas(bt, d);
  thomas(bt, u);
  const double factor = (d[0] + a / g * d[n - 1]) / (1.0 + u[0] + a / g * u[n - 1]);
  for (std::size_t k = 0; k < n; ++k) d[k] -= factor * u[k];
}

// `sweeps` zebra line sweeps over the level's fill cells: the even rows, then the odd ones, each
// row's fill cells solved exactly given the rows above and below, for the change of their values
// from their residuals (so the GPU's float rounding falls on the change: by the poles a whole
// row's system is nearly singular) (the azimuthal coupling grows as
// 1 / sin^2(theta) over the polar one towards the poles, where point relaxation barely moves).
void sweep(Level& l, int sweeps) {
  std::vector<double> b, d;
  std::vector<std::size_t> cells;
  for (int it = 0; it < sweeps; ++it) {
    for (int colour = 0; colour < 2; ++colour) {
      for (int i = colour; i < l.h; i += 2) {
        const RowWeights r = row_weights(i, l.h);
        const std::size_t row = at(l, i, 0);
        // The row's runs of fill cells, each from a cell whose left neighbour is not to fill
        // (the whole row, cyclic, when every cell is).
        int first = -1;
        for (int j = 0; j < l.w; ++j) {
          if (l.kind[row + std::size_t(j)] != kFill) {
            first = j;
            break;
          }
        }
        const bool cyclic = first < 0;
        const int start = cyclic ? 0 : first;
        for (int step = 0; step < l.w;) {
          const int j0 = (start + step) % l.w;
          if (l.kind[row + std::size_t(j0)] != kFill) {
            ++step;
            continue;
          }
          b.clear();
          d.clear();
          cells.clear();
          while (step < l.w && l.kind[row + std::size_t((start + step) % l.w)] == kFill) {
            const int j = (start + step) % l.w;
            const Equation e = equation(l, i, j, r);
            b.push_back(e.own);
            d.push_back(e.residual);
            cells.push_back(row + std::size_t(j));
            ++step;
          }
          solve_row(b, d, -r.azimuthal, cyclic);
          for (std::size_t n = 0; n < cells.size(); ++n) l.v[cells[n]] += d[n];
        }
      }
    }
  }
}

// The residual f - A v at the level's fill cells (0 elsewhere).
std::vector<double> residual(const Level& l) {
  std::vector<double> res(l.v.size(), 0.0);
  for (int i = 0; i < l.h; ++i) {
    const RowWeights r = row_weights(i, l.h);
    for (int j = 0; j < l.w; ++j) {
      const std::size_t k = at(l, i, j);
      if (l.kind[k] == kFill) res[k] = equation(l, i, j, r).residual;
    }
  }
  return res;
}

// One V-cycle from level l down (the correction scheme): smooth, the residual summed into the
// coarser level's right-hand side (the equations are scaled by each cell's area, so sums are
// consistent), its correction solved there, added back by injection, smooth again.
void vcycle(std::vector<Level>& levels, std::size_t l, const MembraneFillParams& params) {
  Level& fine = levels[l];
  if (l + 1 == levels.size()) {
    sweep(fine, params.coarsest_sweeps);
    return;
  }
  sweep(fine, params.sweeps);
  const std::vector<double> res = residual(fine);
  Level& coarse = levels[l + 1];
  std::fill(coarse.v.begin(), coarse.v.end(), 0.0);
  std::fill(coarse.f.begin(), coarse.f.end(), 0.0);
  for (int i = 0; i < fine.h; ++i)
    for (int j = 0; j < fine.w; ++j) coarse.f[at(coarse, i / 2, j / 2)] += res[at(fine, i, j)];
  vcycle(levels, l + 1, params);
  for (int i = 0; i < fine.h; ++i)
    for (int j = 0; j < fine.w; ++j) {
      const std::size_t k = at(fine, i, j);
      if (fine.kind[k] == kFill) fine.v[k] += coarse.v[at(coarse, i / 2, j / 2)];
    }
  sweep(fine, params.sweeps);
}

// The next coarser level of the multigrid: a cell is to fill when its four children are (so the
// coarse regions stay inside the fine ones, whose operator is definite: grown by their rims, they
// would near the hemisphere at the coarsest grid, where the plane's own mode makes it singular),
// else known (its correction 0) when any child takes part.
Level coarser(const Level& f) {
  Level c{f.w / 2, f.h / 2, {}, {}};
  c.v.assign(std::size_t(c.w) * std::size_t(c.h), 0.0);
  c.f = c.v;
  c.kind.assign(c.v.size(), kNeither);
  for (int i = 0; i < c.h; ++i) {
    for (int j = 0; j < c.w; ++j) {
      int fills = 0, any = 0;
      for (int q = 0; q < 4; ++q) {
        const char kind = f.kind[at(f, 2 * i + q / 2, 2 * j + q % 2)];
        fills += kind == kFill;
        any += kind != kNeither;
      }
      c.kind[at(c, i, j)] = fills == 4 ? kFill : any > 0 ? kKnown : kNeither;
    }
  }
  return c;
}

// Solves the fill cells by multigrid V-cycles (kMultigrid), started at `mean`.
void solve_multigrid(std::vector<double>& v, const std::vector<char>& kind, int w, int h,
                     double mean, const MembraneFillParams& params) {
  std::vector<Level> levels{{w, h, v, kind}};
  while (levels.back().h > 8 && levels.back().h % 2 == 0) levels.push_back(coarser(levels.back()));
  for (std::size_t k = 0; k < v.size(); ++k)
    if (kind[k] == kFill) levels[0].v[k] = mean;
  for (int c = 0; c < params.cycles; ++c) vcycle(levels, 0, params);
  v = std::move(levels[0].v);
}

}  // namespace

FloatImage membrane_fill_cpu(const FloatImage& distance, const FloatImage& confidence,
                             const MembraneFillParams& params, double min_distance,
                             double max_distance) {
  params.check();
  require_same_size("membrane fill",
                    {sized("distance", distance), sized("confidence", confidence)});
  const int width = distance.width(), height = distance.height(), c = params.cell;
  params.check_panorama(width, height);
  if (!(min_distance > 0 && max_distance > min_distance))
    throw std::invalid_argument("membrane fill: the distance range must be 0 < min < max");
  const int w = width / c, h = height / c;
  const auto cells = std::size_t(w) * std::size_t(h);

  // 1. Known cells and their mean inverse distance.
  std::vector<double> v(cells, 0.0);
  std::vector<int> count(cells, 0);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const float d = distance(x, y);
      if (d > 0 && confidence(x, y) >= params.known_from) {
        const std::size_t k = std::size_t(y / c) * std::size_t(w) + std::size_t(x / c);
        v[k] += 1.0 / d;
        ++count[k];
      }
    }
  }
  std::vector<char> known(cells, 0);
  double mean = 0;
  int known_cells = 0;
  for (std::size_t k = 0; k < cells; ++k) {
    if (count[k] > 0 && count[k] >= params.known_share * c * c) {
      known[k] = 1;
      v[k] /= count[k];
      mean += v[k];
      ++known_cells;
    }
  }
  FloatImage out = distance.clone();
  if (known_cells == 0) return out;  // nothing to take a boundary from
  mean /= known_cells;

  // 2. The components large enough to fill.
  std::vector<int> sizes;
  const std::vector<int> label = components(known, w, h, sizes);
  std::vector<char> kind(cells, kNeither);
  for (std::size_t k = 0; k < cells; ++k) {
    if (known[k])
      kind[k] = kKnown;
    else if (sizes[std::size_t(label[k])] >= params.min_cells)
      kind[k] = kFill;
    else
      v[k] = mean;  // not solved; the interpolation of step 4 can reach one diagonally
  }

  // 3. (Laplace_S + 2) v = 0 on the cells to fill, the known cells as boundary values; row i's
  // centre at polar angle (i + 1/2) step. Times sin(theta_i) step^2, per cell:
  //   sin(theta_i+1/2) (v_s - v) + sin(theta_i-1/2) (v_n - v) + (v_e + v_w - 2 v) / sin(theta_i)
  //   + 2 step^2 sin(theta_i) v = 0.
  if (params.solver == MembraneSolver::kDirect) {
    if (!solve_direct(v, kind, w, h)) return out;  // singular: leave the distances as they are
  } else {
    solve_multigrid(v, kind, w, h, mean, params);
  }

  // 4. The unconfident pixels of filled components take the field.
  const double lo = 1.0 / max_distance, hi = 1.0 / min_distance;
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const std::size_t k = std::size_t(y / c) * std::size_t(w) + std::size_t(x / c);
      if (kind[k] != kFill || !(distance(x, y) > 0) || confidence(x, y) >= params.fill_below)
        continue;
      const double fy = std::clamp((y + 0.5) / c - 0.5, 0.0, h - 1.0);
      const double fx = (x + 0.5) / c - 0.5;
      const int y0 = std::min(int(fy), h - 2 < 0 ? 0 : h - 2);
      const int y1 = std::min(y0 + 1, h - 1);
      const double ay = fy - y0;
      const int x0 = int(std::floor(fx));
      const double ax = fx - x0;
      const auto at = [&](int i, int j) {
        return v[std::size_t(i) * std::size_t(w) + std::size_t(((j % w) + w) % w)];
      };
      const double field = (1 - ay) * ((1 - ax) * at(y0, x0) + ax * at(y0, x0 + 1)) +
                           ay * ((1 - ax) * at(y1, x0) + ax * at(y1, x0 + 1));
      out(x, y) = float(1.0 / std::clamp(field, lo, hi));
    }
  }
  return out;
}

}  // namespace omnisweep::stitch
