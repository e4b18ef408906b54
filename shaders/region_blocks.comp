#version 450
#extension GL_GOOGLE_include_directive : require
// Region planes, step 1 (server/stitch/region_planes.h): per block of push.block^2 pixels, its
// unconfident pixels (a distance, confidence < fill_below) and its most confident pixel of at
// least `support` (the first of equals) with that pixel's inverse distance; the union-find's
// parents start as the block itself for a block with an unconfident pixel, kNone otherwise.
layout(local_size_x_id = 100, local_size_y_id = 101, local_size_z_id = 102) in;

layout(std430, set = 0, binding = 0) readonly buffer Distance { float distance[]; };
layout(std430, set = 0, binding = 1) readonly buffer Confidence { float confidence[]; };
layout(std430, set = 0, binding = 2) writeonly buffer Blocks { uvec4 blocks[]; };
layout(std430, set = 0, binding = 3) writeonly buffer Parent { uint parent[]; };
layout(std430, set = 0, binding = 4) writeonly buffer Sizes { uint sizes[]; };
#include "region_planes.glsl"

void main() {
  const ivec2 bp = ivec2(gl_GlobalInvocationID.xy);
  if (bp.x >= push.blocks_x || bp.y >= push.blocks_y) return;
  const int w = int(push.width), h = int(push.height);
  const uint b = uint(bp.y * push.blocks_x + bp.x);
  uint low = 0u, pick = kNone;
  float best = -1.0, v = 0.0;
  for (int y = bp.y * push.block; y < min(h, (bp.y + 1) * push.block); ++y) {
    for (int x = bp.x * push.block; x < min(w, (bp.x + 1) * push.block); ++x) {
      const uint i = uint(y * w + x);
      const float d = distance[i], c = confidence[i];
      if (!(d > 0.0)) continue;
      if (c < push.fill_below) ++low;
      if (c >= push.support && c > best) {
        best = c;
        pick = i;
        v = 1.0 / d;
      }
    }
  }
  blocks[b] = uvec4(low, pick, floatBitsToUint(v), 0u);
  parent[b] = low > 0u ? b : kNone;
  sizes[b] = 0u;
}
