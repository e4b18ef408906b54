#version 450
#extension GL_GOOGLE_include_directive : require
// Region planes, step 3a (server/stitch/region_planes.h): a block's support pixel supports the
// regions (the first kNearRegions, in scan order) with a block within `rim` blocks (a disk).
// Phase 0 counts each region's histogram of its supports' hashes' top 8 bits; phase 1
// (after region_threshold.comp) collects the candidates of the bins up to the region's last
// sampled bin, in any order (region_sample.comp sorts them).
layout(local_size_x_id = 100, local_size_y_id = 101, local_size_z_id = 102) in;

layout(std430, set = 0, binding = 0) readonly buffer Blocks { uvec4 blocks[]; };
layout(std430, set = 0, binding = 1) readonly buffer Parent { uint parent[]; };
layout(std430, set = 0, binding = 2) readonly buffer Slots { uint slots[]; };
layout(std430, set = 0, binding = 3) buffer Regions { uint regions[]; };
layout(std430, set = 0, binding = 4) buffer Histogram { uint histogram[]; };
layout(std430, set = 0, binding = 5) writeonly buffer Candidates { uvec2 candidates[]; };
#include "region_planes.glsl"

void main() {
  const ivec2 bp = ivec2(gl_GlobalInvocationID.xy);
  const int bw = push.blocks_x, bh = push.blocks_y;
  if (bp.x >= bw || bp.y >= bh) return;
  const uint b = uint(bp.y * bw + bp.x);
  if (blocks[b].y == kNone || regions[0] == 0u) return;
  int list[kNearRegions];
  int count = 0;
  for (int dy = -push.rim; dy <= push.rim && count < kNearRegions; ++dy) {
    const int y = bp.y + dy;
    if (y < 0 || y >= bh) continue;
    for (int dx = -push.rim; dx <= push.rim && count < kNearRegions; ++dx) {
      if (dx * dx + dy * dy > push.rim * push.rim) continue;
      const uint root = parent[uint(y * bw + ((bp.x + dx) % bw + bw) % bw)];
      if (root == kNone) continue;
      const uint s = slots[root];
      if (s == kNone) continue;
      bool seen = false;
      for (int k = 0; k < count; ++k) seen = seen || list[k] == int(s);
      if (!seen) list[count++] = int(s);
    }
  }
  for (int k = 0; k < count; ++k) {
    const int l = list[k];
    const uint key = support_hash(b, regions[field(l, kRoot)]);
    const uint bin = key >> 24u;
    if (push.phase == 0) {
      atomicAdd(histogram[l * 256 + int(bin)], 1u);
    } else if (int(bin) <= int(regions[field(l, kLastBin)])) {
      const uint at = atomicAdd(regions[field(l, kCollected)], 1u);
      if (at < uint(kCandidates)) candidates[l * kCandidates + int(at)] = uvec2(key, b);
    }
  }
}
