#version 450
#extension GL_GOOGLE_include_directive : require
// Region planes, step 4a (server/stitch/region_planes.h): one invocation per (draw, region) for
// the plane push.plane: the plane through three of the region's alive supports drawn by
// draw_hash, scored by MSAC over every alive support in order; `scores` gets (a, score), the
// score -1 where the three are degenerate. region_refit.comp then picks the best.
layout(local_size_x_id = 100, local_size_y_id = 101, local_size_z_id = 102) in;

layout(std430, set = 0, binding = 0) readonly buffer Regions { uint regions[]; };
layout(std430, set = 0, binding = 1) readonly buffer Sample { vec4 sample_[]; };
layout(std430, set = 0, binding = 2) readonly buffer Alive { uint alive[]; };
layout(std430, set = 0, binding = 3) writeonly buffer Scores { vec4 scores[]; };
#include "region_planes.glsl"

void main() {
  const int d = int(gl_GlobalInvocationID.x), l = int(gl_GlobalInvocationID.y);
  if (d >= push.draws || l >= int(regions[0]) || regions[field(l, kDone)] != 0u) return;
  const uint count = regions[field(l, kAlive)];
  if (count < 3u) return;
  const uint root = regions[field(l, kRoot)];
  const int base = l * kSample;
  vec4 s[3];
  for (int t = 0; t < 3; ++t)
    s[t] = sample_[base + int(alive[base + int(draw_hash(root, uint(push.plane),
                                                          uint(3 * d + t)) % count)])];
  vec3 a;
  float score = -1.0;
  if (solve3(s[0].xyz, s[1].xyz, s[2].xyz, vec3(s[0].w, s[1].w, s[2].w), 1e-6, a)) {
    score = 0.0;
    for (uint i = 0u; i < count; ++i) score += msac(a, sample_[base + int(alive[base + int(i)])]);
  }
  scores[l * push.draws + d] = vec4(a, score);
}
