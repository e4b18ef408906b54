// Membrane fill (docs/accuracy.md, stop 47; the CPU reference, not yet in the stitcher): on a
// plane, the inverse distance seen along a unit ray r is linear in r, 1/D = a . r, and on the
// sphere such a function solves (Laplace_S + 2) v = 0. Solving that equation inside each large
// unconfident region, with the confident inverse distances around it as the boundary values,
// gives back a plane exactly where the region's boundary lies on one (a plain ceiling inside its
// creases with the walls) and blends smoothly where it lies on several; it is deterministic and
// continuous in its inputs, where a RANSAC over the boundary (region_planes.h) is neither.
//
// On a grid `cell` times coarser than the panorama:
//   1. a cell is known when at least known_share of its pixels have a distance and a confidence
//      of at least known_from; its value is their mean inverse distance;
//   2. the unknown cells form 4-connected components (wrapping left to right); those of fewer
//      than min_cells cells are left alone;
//   3. the field solves (Laplace_S + 2) v = 0 on the other unknown cells, the known ones fixed,
//      in the equirectangular grid's own metric: the polar flux weighted by sin(theta) at the
//      cells' edges (0 at the poles, which need no boundary condition), the azimuthal by
//      1 / sin(theta). MembraneSolver::kMultigrid (the product's, written to run as well on the
//      GPU): `cycles` V-cycles of the correction scheme over a pyramid of grids, each half the
//      last's size down to 8 rows, each level smoothed by `sweeps` zebra line sweeps before and
//      after its coarse correction (the even rows, then the odd ones, each row's run of cells to
//      fill solved exactly given the rows beside it: towards the poles the azimuthal coupling
//      grows as 1 / sin^2(theta) over the polar one, where point relaxation barely moves), the
//      coarsest given coarsest_sweeps. kDirect solves the fine system exactly (Eigen's sparse
//      LU; nothing is filled where it is singular: a region as large as a hemisphere), the oracle
//      the multigrid is measured against;
//   4. each pixel with a distance and a confidence below fill_below, in a filled component,
//      takes the field interpolated bilinearly between the cells' centres (clamped to the
//      sweep's range).
// The discretisation and the multigrid are written by hand (no library here knows the sphere's
// grid, and the same steps are to run on the GPU); Eigen's sparse LU solves it directly (at most
// 256 x 128 cells at 2048 x 1024). Over the panoramas of `--match-blur 1 --no-region-planes` the
// multigrid's MAE equals the direct solve's to 4 digits (docs/accuracy.md).
#pragma once

#include "omnisweep/gpu/buffer.h"
#include "omnisweep/gpu/kernel.h"
#include "omnisweep/gpu/sequence.h"
#include "omnisweep/image/image.h"

namespace omnisweep::stitch {

enum class MembraneSolver { kMultigrid, kDirect };

// The settings at a 2048 x 1024 panorama (the cell scales with the width, min_cells not: it
// counts cells, which hold the same solid angle at every width).
struct MembraneFillParams {
  double fill_below = 0.1;    // pixels of lower confidence take the field
  double known_from = 0.1;    // a cell's boundary pixels: of at least this confidence
  double known_share = 0.25;  // a cell is known when this share of its pixels are such pixels
  int cell = 8;               // pixels per cell side
  int min_cells = 1000;       // smaller components of unknown cells are left alone
  MembraneSolver solver = MembraneSolver::kMultigrid;
  int cycles = 6;            // V-cycles (kMultigrid)
  int sweeps = 4;            // line sweeps before and after each coarse correction (kMultigrid)
  int coarsest_sweeps = 30;  // line sweeps on the coarsest grid (kMultigrid)
  // For a panorama `width` pixels wide: the cell scaled from 2048.
  static MembraneFillParams for_width(int width);
  // Throws std::invalid_argument naming a setting out of range.
  void check() const;
  // Throws std::invalid_argument where a width x height panorama is not 2:1 or not a whole
  // number of cells.
  void check_panorama(int width, int height) const;
};

// `distance` (metres, 0 = none) with its large unconfident regions filled as above; every other
// pixel is copied. Throws std::invalid_argument when the images differ in size, the panorama is
// not 2:1 or not a whole number of cells, or a setting is out of range.
FloatImage membrane_fill_cpu(const FloatImage& distance, const FloatImage& confidence,
                             const MembraneFillParams& params, double min_distance,
                             double max_distance);

// The membrane fill on the GPU (the membrane_*.comp kernels, five dispatches; the solve is one
// workgroup of 1024 invocations, steps 1-3 of membrane_fill_cpu with MembraneSolver::kMultigrid,
// in float). Keep the two in step.
class MembraneFill {
 public:
  // Throws std::invalid_argument as membrane_fill_cpu does, or where params.solver is kDirect.
  MembraneFill(gpu::Context& context, int width, int height, const MembraneFillParams& params,
               double min_distance, double max_distance);

  // Records the fill into `seq` after what writes `distance` (float metres) and `confidence`;
  // `distance` is rewritten in place.
  void record(gpu::Sequence& seq, gpu::Buffer& distance, const gpu::Buffer& confidence) const;

 private:
  int width_, height_;
  MembraneFillParams params_;
  double min_distance_, max_distance_;
  int w_, h_, levels_;
  gpu::Buffer value_;    // per cell of every level: the field (fine), the corrections (coarser)
  gpu::Buffer rhs_;      // per cell of every level: the right-hand side
  gpu::Buffer kind_;     // per cell of every level (membrane_fill.glsl's kinds)
  gpu::Buffer parent_;   // per fine cell: union-find parent, then the root
  gpu::Buffer sizes_;    // per fine cell (as root): its component's cells
  gpu::Buffer scratch_;  // the line solves' three vectors, a fine grid each
  gpu::Kernel cells_, merge_, flatten_, solve_, apply_;
};

}  // namespace omnisweep::stitch
