#version 450
#extension GL_GOOGLE_include_directive : require
// Region planes, step 2a (server/stitch/region_planes.h): the union-find over the blocks with an
// unconfident pixel, each united with its left (wrapping), upper-left, upper and upper-right
// neighbours (union_find.glsl: a component's root is its least block).
layout(local_size_x_id = 100, local_size_y_id = 101, local_size_z_id = 102) in;

layout(std430, set = 0, binding = 0) coherent volatile buffer Parent { uint parent[]; };
#include "region_planes.glsl"
#include "union_find.glsl"

void main() {
  const ivec2 bp = ivec2(gl_GlobalInvocationID.xy);
  const int bw = push.blocks_x;
  if (bp.x >= bw || bp.y >= push.blocks_y) return;
  const uint b = uint(bp.y * bw + bp.x);
  if (parent[b] == kNone) return;
  const uint left = uint(bp.y * bw + (bp.x + bw - 1) % bw);
  if (parent[left] != kNone) unite(b, left);
  if (bp.y == 0) return;
  for (int dx = -1; dx <= 1; ++dx) {
    const uint j = uint((bp.y - 1) * bw + (bp.x + dx + bw) % bw);
    if (parent[j] != kNone) unite(b, j);
  }
}
