// Shared by the membrane_*.comp kernels (server/stitch/membrane_fill.h): their push constants,
// the cells' kinds and the multigrid's levels (level l: (w >> l) x (h >> l) cells, stored after
// the finer levels' in the value, rhs and kind buffers).

layout(push_constant) uniform Push {
  uint width;  // the panorama
  uint height;
  int cell;       // pixels per cell side
  int w;          // the fine grid
  int h;
  int levels;     // of the multigrid (1: the fine grid alone)
  int min_cells;  // smaller components of unknown cells are left alone
  int min_count;  // a cell is known with at least this many pixels of a confident distance
  int cycles;
  int sweeps;
  int coarsest_sweeps;
  float known_from;
  float fill_below;
  float inv_d_min;  // the largest inverse distance
  float inv_d_max;  // the smallest
  int phase;        // membrane_solve: 0 the kinds, 1 a V-cycle's way down, 2 its way up
} push;

const uint kNone = 0xffffffffu;
// A cell's kind (membrane_fill.cc's Kind); membrane_cells marks every unknown cell kUnknown,
// which membrane_solve makes kFill or kNeither by its component's size.
const uint kNeither = 0u;
const uint kKnown = 1u;
const uint kFill = 2u;
const uint kUnknown = 3u;
