#version 450
#extension GL_GOOGLE_include_directive : require
// Region planes, step 2b (server/stitch/region_planes.h): each block with an unconfident pixel
// points straight at its component's root, which sums the component's unconfident pixels.
layout(local_size_x_id = 100, local_size_y_id = 101, local_size_z_id = 102) in;

layout(std430, set = 0, binding = 0) readonly buffer Blocks { uvec4 blocks[]; };
layout(std430, set = 0, binding = 1) coherent volatile buffer Parent { uint parent[]; };
layout(std430, set = 0, binding = 2) buffer Sizes { uint sizes[]; };
#include "region_planes.glsl"

void main() {
  const ivec2 bp = ivec2(gl_GlobalInvocationID.xy);
  if (bp.x >= push.blocks_x || bp.y >= push.blocks_y) return;
  const uint b = uint(bp.y * push.blocks_x + bp.x);
  uint i = parent[b];
  if (i == kNone) return;
  uint p = parent[i];
  while (p != i) {
    i = p;
    p = parent[i];
  }
  parent[b] = i;
  atomicAdd(sizes[i], blocks[b].x);
}
