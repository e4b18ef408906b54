#version 450
#extension GL_GOOGLE_include_directive : require
// Region planes, step 3c (server/stitch/region_planes.h), one workgroup per region: its
// candidates sorted by (hash, block) (a bitonic sort in shared memory), the first kSample of
// them its sample: (ray, inverse distance) of each one's support pixel; the RANSAC's state
// starts over (every support alive, no tags, no planes).
layout(local_size_x_id = 100, local_size_y_id = 101, local_size_z_id = 102) in;

layout(std430, set = 0, binding = 0) readonly buffer Blocks { uvec4 blocks[]; };
layout(std430, set = 0, binding = 1) buffer Regions { uint regions[]; };
layout(std430, set = 0, binding = 2) readonly buffer Candidates { uvec2 candidates[]; };
layout(std430, set = 0, binding = 3) readonly buffer Table { vec2 table[]; };
layout(std430, set = 0, binding = 4) writeonly buffer Sample { vec4 sample_[]; };
layout(std430, set = 0, binding = 5) writeonly buffer Alive { uint alive[]; };
layout(std430, set = 0, binding = 6) writeonly buffer Tags { int tags[]; };
#define REGION_RAYS
#include "region_planes.glsl"

const uint kThreads = 1024u;  // the workgroup (set by the host): kCandidates / 2
shared uvec2 keys[kCandidates];

bool before(uvec2 a, uvec2 b) { return a.x < b.x || (a.x == b.x && a.y < b.y); }

void main() {
  const int l = int(gl_WorkGroupID.x);
  const uint t = gl_LocalInvocationID.x;
  if (l >= int(regions[0])) return;
  const uint collected = min(regions[field(l, kCollected)], uint(kCandidates));
  for (uint i = t; i < uint(kCandidates); i += kThreads)
    keys[i] = i < collected ? candidates[l * kCandidates + int(i)] : uvec2(kNone);
  barrier();
  for (uint size = 2u; size <= uint(kCandidates); size <<= 1) {
    for (uint stride = size >> 1; stride > 0u; stride >>= 1) {
      // Each thread compares one pair (i, i ^ stride), i with the stride bit clear.
      const uint i = 2u * t - (t & (stride - 1u));
      const uint j = i + stride;
      const bool ascending = (i & size) == 0u;
      const uvec2 a = keys[i], b = keys[j];
      if (before(b, a) == ascending) {
        keys[i] = b;
        keys[j] = a;
      }
      barrier();
    }
  }
  const uint n = min(collected, uint(kSample));
  for (uint i = t; i < n; i += kThreads) {
    const uvec4 block = blocks[keys[i].y];
    const int w = int(push.width);
    sample_[l * kSample + int(i)] =
        vec4(ray(int(block.y) % w, int(block.y) / w), uintBitsToFloat(block.z));
    alive[l * kSample + int(i)] = i;
    tags[l * kSample + int(i)] = -1;
  }
  if (t == 0u) {
    regions[field(l, kSampled)] = n;
    regions[field(l, kAlive)] = n;
    regions[field(l, kPlanes)] = 0u;
    regions[field(l, kDone)] = n < 3u ? 1u : 0u;
  }
}
