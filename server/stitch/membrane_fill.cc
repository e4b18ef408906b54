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

}  // namespace

FloatImage membrane_fill_cpu(const FloatImage& distance, const FloatImage& confidence,
                             const MembraneFillParams& params, double min_distance,
                             double max_distance) {
  params.check();
  require_same_size("membrane fill",
                    {sized("distance", distance), sized("confidence", confidence)});
  const int width = distance.width(), height = distance.height(), c = params.cell;
  if (width != 2 * height || width % c != 0 || height % c != 0) {
    throw std::invalid_argument(
        "membrane fill: the panorama is " + std::to_string(width) + "x" + std::to_string(height) +
        "; it must be 2:1 and a whole number of cells of " + std::to_string(c) + " pixels");
  }
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
  std::vector<char> fill(cells, 0);
  for (std::size_t k = 0; k < cells; ++k) {
    fill[k] = !known[k] && sizes[std::size_t(label[k])] >= params.min_cells;
    // The unknown cells of small components are not solved; the interpolation of step 4 can
    // reach one diagonally, and takes the known cells' mean there.
    if (!known[k] && !fill[k]) v[k] = mean;
  }

  // 3. (Laplace_S + 2) v = 0 on the cells to fill, the known cells as boundary values; row i's
  // centre at polar angle (i + 1/2) step. Times sin(theta_i) step^2, per cell:
  //   sin(theta_i+1/2) (v_s - v) + sin(theta_i-1/2) (v_n - v) + (v_e + v_w - 2 v) / sin(theta_i)
  //   + 2 step^2 sin(theta_i) v = 0,
  // a sparse linear system, solved directly (Eigen's SparseLU: it is not positive definite
  // where a region is as large as a hemisphere).
  const double step = std::numbers::pi / h;
  const auto rows = std::size_t(h);
  std::vector<double> north(rows), south(rows), azimuthal(rows), own(rows);
  for (std::size_t i = 0; i < rows; ++i) {
    north[i] = std::sin(double(i) * step);
    south[i] = std::sin(double(i + 1) * step);
    const double s = std::sin((double(i) + 0.5) * step);
    azimuthal[i] = 1.0 / s;
    own[i] = north[i] + south[i] + 2.0 * azimuthal[i] - 2.0 * step * step * s;
  }
  std::vector<int> unknown_index(cells, -1);
  int unknowns = 0;
  for (std::size_t k = 0; k < cells; ++k) {
    if (fill[k]) unknown_index[k] = unknowns++;
  }
  if (unknowns == 0) return out;
  std::vector<Eigen::Triplet<double>> entries;
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(unknowns);
  for (std::size_t k = 0; k < cells; ++k) {
    const int row = unknown_index[k];
    if (row < 0) continue;
    const std::size_t i = k / std::size_t(w), j = k % std::size_t(w);
    entries.emplace_back(row, row, own[i]);
    const auto couple = [&](std::size_t q, double weight) {
      if (unknown_index[q] >= 0)
        entries.emplace_back(row, unknown_index[q], -weight);
      else
        rhs[row] += weight * v[q];  // a known cell: the components are maximal
    };
    const auto ww = std::size_t(w);
    couple(i * ww + (j + 1) % ww, azimuthal[i]);
    couple(i * ww + (j + ww - 1) % ww, azimuthal[i]);
    if (i > 0) couple(k - ww, north[i]);
    if (i + 1 < rows) couple(k + ww, south[i]);
  }
  Eigen::SparseMatrix<double> system(unknowns, unknowns);
  system.setFromTriplets(entries.begin(), entries.end());
  Eigen::SparseLU<Eigen::SparseMatrix<double>> solver;
  solver.compute(system);
  if (solver.info() != Eigen::Success) return out;  // singular: leave the distances as they are
  const Eigen::VectorXd solution = solver.solve(rhs);
  for (std::size_t k = 0; k < cells; ++k) {
    if (unknown_index[k] >= 0) v[k] = solution[unknown_index[k]];
  }

  // 4. The unconfident pixels of filled components take the field.
  const double lo = 1.0 / max_distance, hi = 1.0 / min_distance;
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const std::size_t k = std::size_t(y / c) * std::size_t(w) + std::size_t(x / c);
      if (!fill[k] || !(distance(x, y) > 0) || confidence(x, y) >= params.fill_below) continue;
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
