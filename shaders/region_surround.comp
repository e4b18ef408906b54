#version 450
#extension GL_GOOGLE_include_directive : require
// Region planes, step 5 (server/stitch/region_planes.h): per block of a region with planes, the
// planes whose inliers (the sample's supports tagged with them) within the surround's angle of
// the block's centre ray (push.surround_cos) lie in at least three of the four quadrants of the
// tangent plane at that ray; `surround` gets (planes as bits, region), (0, kNone) elsewhere.
layout(local_size_x_id = 100, local_size_y_id = 101, local_size_z_id = 102) in;

layout(std430, set = 0, binding = 0) readonly buffer Parent { uint parent[]; };
layout(std430, set = 0, binding = 1) readonly buffer Slots { uint slots[]; };
layout(std430, set = 0, binding = 2) readonly buffer Regions { uint regions[]; };
layout(std430, set = 0, binding = 3) readonly buffer Sample { vec4 sample_[]; };
layout(std430, set = 0, binding = 4) readonly buffer Tags { int tags[]; };
layout(std430, set = 0, binding = 5) readonly buffer Table { vec2 table[]; };
layout(std430, set = 0, binding = 6) writeonly buffer Surround { uvec2 surround[]; };
#define REGION_RAYS
#include "region_planes.glsl"

void main() {
  const ivec2 bp = ivec2(gl_GlobalInvocationID.xy);
  if (bp.x >= push.blocks_x || bp.y >= push.blocks_y) return;
  const uint b = uint(bp.y * push.blocks_x + bp.x);
  surround[b] = uvec2(0u, kNone);
  const uint root = parent[b];
  if (root == kNone) return;
  const uint l = slots[root];
  if (l == kNone || regions[field(int(l), kPlanes)] == 0u) return;
  const vec3 centre = ray(min(int(push.width) - 1, bp.x * push.block + push.block / 2),
                          min(int(push.height) - 1, bp.y * push.block + push.block / 2));
  uvec2 quadrants = uvec2(0u);  // 4 bits per plane: planes 0-7 in x, 8-15 in y
  const int base = int(l) * kSample;
  const int n = int(regions[field(int(l), kSampled)]);
  for (int j = 0; j < n; ++j) {
    const int k = tags[base + j];
    if (k < 0) continue;
    const uint q = quadrant(centre, sample_[base + j].xyz);
    if (k < 8)
      quadrants.x |= q << (4 * k);
    else
      quadrants.y |= q << (4 * (k - 8));
  }
  uint mask = 0u;
  for (int k = 0; k < kMaxPlanes; ++k) {
    const uint bits = ((k < 8 ? quadrants.x : quadrants.y) >> (4 * (k & 7))) & 15u;
    if (bitCount(bits) >= 3) mask |= 1u << k;
  }
  surround[b] = uvec2(mask, l);
}
