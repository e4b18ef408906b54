#version 450
#extension GL_GOOGLE_include_directive : require
// Membrane fill, step 2b (server/stitch/membrane_fill.h): each unknown cell points straight at
// its component's root, which counts the component's cells.
layout(local_size_x_id = 100, local_size_y_id = 101, local_size_z_id = 102) in;

layout(std430, set = 0, binding = 0) coherent volatile buffer Parent { uint parent[]; };
layout(std430, set = 0, binding = 1) buffer Sizes { uint sizes[]; };
#include "membrane_fill.glsl"

void main() {
  const ivec2 cp = ivec2(gl_GlobalInvocationID.xy);
  if (cp.x >= push.w || cp.y >= push.h) return;
  const uint k = uint(cp.y * push.w + cp.x);
  uint i = parent[k];
  if (i == kNone) return;
  uint p = parent[i];
  while (p != i) {
    i = p;
    p = parent[i];
  }
  parent[k] = i;
  atomicAdd(sizes[i], 1u);
}
