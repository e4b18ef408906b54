#version 450
#extension GL_GOOGLE_include_directive : require
// Membrane fill, step 1 (server/stitch/membrane_fill.h): per cell, known when at least min_count
// of its pixels have a distance and a confidence >= known_from, its value their mean inverse
// distance; else unknown, the union-find's parent the cell itself (kNone for a known cell); the
// components' sizes start at 0.
layout(local_size_x_id = 100, local_size_y_id = 101, local_size_z_id = 102) in;

layout(std430, set = 0, binding = 0) readonly buffer Distance { float distance[]; };
layout(std430, set = 0, binding = 1) readonly buffer Confidence { float confidence[]; };
layout(std430, set = 0, binding = 2) writeonly buffer Value { float value[]; };
layout(std430, set = 0, binding = 3) writeonly buffer Kind { uint kind[]; };
layout(std430, set = 0, binding = 4) writeonly buffer Parent { uint parent[]; };
layout(std430, set = 0, binding = 5) writeonly buffer Sizes { uint sizes[]; };
#include "membrane_fill.glsl"

void main() {
  const ivec2 cp = ivec2(gl_GlobalInvocationID.xy);
  if (cp.x >= push.w || cp.y >= push.h) return;
  const uint k = uint(cp.y * push.w + cp.x);
  const int c = push.cell, width = int(push.width);
  float sum = 0.0;
  int count = 0;
  for (int y = cp.y * c; y < (cp.y + 1) * c; ++y) {
    for (int x = cp.x * c; x < (cp.x + 1) * c; ++x) {
      const uint i = uint(y * width + x);
      const float d = distance[i];
      if (d > 0.0 && confidence[i] >= push.known_from) {
        sum += 1.0 / d;
        ++count;
      }
    }
  }
  const bool known = count >= push.min_count;
  value[k] = known ? sum / float(count) : 0.0;
  kind[k] = known ? kKnown : kUnknown;
  parent[k] = known ? kNone : k;
  sizes[k] = 0u;
}
