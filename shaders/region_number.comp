#version 450
#extension GL_GOOGLE_include_directive : require
// Region planes, step 2c (server/stitch/region_planes.h), one workgroup: the components with at
// least min_pixels unconfident pixels become regions 0.. in the order of their roots (a prefix
// sum over the blocks, so the numbering does not depend on scheduling), at most max_regions;
// `slots` gets each root's region (kNone elsewhere), the records and histograms start empty.
layout(local_size_x_id = 100, local_size_y_id = 101, local_size_z_id = 102) in;

layout(std430, set = 0, binding = 0) readonly buffer Parent { uint parent[]; };
layout(std430, set = 0, binding = 1) readonly buffer Sizes { uint sizes[]; };
layout(std430, set = 0, binding = 2) writeonly buffer Slots { uint slots[]; };
layout(std430, set = 0, binding = 3) buffer Regions { uint regions[]; };
layout(std430, set = 0, binding = 4) writeonly buffer Histogram { uint histogram[]; };
#include "region_planes.glsl"

const uint kThreads = 1024u;  // the workgroup (set by the host)
shared uint counts[kThreads];

bool is_region(uint b) {
  return parent[b] == b && sizes[b] >= uint(push.min_pixels);
}

void main() {
  const uint t = gl_LocalInvocationID.x;
  const uint nb = uint(push.blocks_x * push.blocks_y);
  const uint chunk = (nb + kThreads - 1u) / kThreads;
  const uint first = t * chunk, last = min(nb, first + chunk);
  uint count = 0u;
  for (uint b = first; b < last; ++b) count += is_region(b) ? 1u : 0u;
  counts[t] = count;
  for (uint i = t; i < uint(push.max_regions) * 256u; i += kThreads) histogram[i] = 0u;
  barrier();
  // Inclusive scan (Hillis-Steele) over the threads' counts.
  for (uint step = 1u; step < kThreads; step <<= 1) {
    const uint add = t >= step ? counts[t - step] : 0u;
    barrier();
    counts[t] += add;
    barrier();
  }
  uint slot = counts[t] - count;
  for (uint b = first; b < last; ++b) {
    uint s = kNone;
    if (is_region(b)) {
      if (slot < uint(push.max_regions)) {
        s = slot;
        for (int f = 0; f < kRecord; ++f) regions[field(int(s), f)] = 0u;
        regions[field(int(s), kRoot)] = b;
      }
      ++slot;
    }
    slots[b] = s;
  }
  if (t == 0u) regions[0] = min(counts[kThreads - 1u], uint(push.max_regions));
}
