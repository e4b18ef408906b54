#version 450
#extension GL_GOOGLE_include_directive : require
// Membrane fill, step 2a (server/stitch/membrane_fill.h): the union-find over the unknown cells,
// each united with its left (wrapping) and upper neighbours: 4-connected components
// (union_find.glsl: a component's root is its least cell).
layout(local_size_x_id = 100, local_size_y_id = 101, local_size_z_id = 102) in;

layout(std430, set = 0, binding = 0) coherent volatile buffer Parent { uint parent[]; };
#include "membrane_fill.glsl"
#include "union_find.glsl"

void main() {
  const ivec2 cp = ivec2(gl_GlobalInvocationID.xy);
  const int w = push.w;
  if (cp.x >= w || cp.y >= push.h) return;
  const uint k = uint(cp.y * w + cp.x);
  if (parent[k] == kNone) return;
  const uint left = uint(cp.y * w + (cp.x + w - 1) % w);
  if (parent[left] != kNone) unite(k, left);
  if (cp.y > 0 && parent[k - uint(w)] != kNone) unite(k, k - uint(w));
}
