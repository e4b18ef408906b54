#version 450
#extension GL_GOOGLE_include_directive : require
// Region planes, step 4b (server/stitch/region_planes.h), one workgroup per region, for the
// plane push.plane: the best of region_hypotheses.comp's draws (the highest score, the first of
// equals); unless it has too few inliers (then the region is done), refitted three times by
// least squares on its inliers (Cramer's rule on the normal equations); its inliers tagged with
// the plane and taken off the alive list, which keeps its order.
layout(local_size_x_id = 100, local_size_y_id = 101, local_size_z_id = 102) in;

layout(std430, set = 0, binding = 0) buffer Regions { uint regions[]; };
layout(std430, set = 0, binding = 1) readonly buffer Sample { vec4 sample_[]; };
layout(std430, set = 0, binding = 2) buffer Alive { uint alive[]; };
layout(std430, set = 0, binding = 3) writeonly buffer Tags { int tags[]; };
layout(std430, set = 0, binding = 4) readonly buffer Scores { vec4 scores[]; };
layout(std430, set = 0, binding = 5) writeonly buffer Planes { vec4 planes[]; };
#include "region_planes.glsl"

const uint kThreads = 256u;  // the workgroup (set by the host)
const uint kPerThread = uint(kSample) / kThreads;
shared uint list[kSample];
shared float best_score[kThreads];
shared int best_draw[kThreads];
shared float sums[kThreads][9];
shared uint kept[kThreads];

// Sums the threads' nine partial sums into sums[0] (every thread calls it).
void reduce_sums() {
  for (uint step = kThreads / 2u; step > 0u; step >>= 1) {
    barrier();
    const uint t = gl_LocalInvocationID.x;
    if (t < step)
      for (int k = 0; k < 9; ++k) sums[t][k] += sums[t + step][k];
  }
  barrier();
}

void main() {
  const int l = int(gl_WorkGroupID.x);
  const uint t = gl_LocalInvocationID.x;
  if (l >= int(regions[0]) || regions[field(l, kDone)] != 0u) return;
  const int base = l * kSample;
  const uint count = regions[field(l, kAlive)];
  const int needed = needed_inliers(int(regions[field(l, kSampled)]), regions[field(l, kSupports)]);
  if (int(count) < needed || count < 3u) {
    if (t == 0u) regions[field(l, kDone)] = 1u;
    return;
  }
  for (uint i = t; i < count; i += kThreads) list[i] = alive[base + int(i)];
  // The best draw.
  float best = -1.0;
  int pick = -1;
  for (int d = int(t); d < push.draws; d += int(kThreads)) {
    const float s = scores[l * push.draws + d].w;
    if (s > best) {
      best = s;
      pick = d;
    }
  }
  best_score[t] = best;
  best_draw[t] = pick;
  for (uint step = kThreads / 2u; step > 0u; step >>= 1) {
    barrier();
    if (t < step) {
      const float o = best_score[t + step];
      const int od = best_draw[t + step];
      if (od >= 0 && (o > best_score[t] || (o == best_score[t] && od < best_draw[t]))) {
        best_score[t] = o;
        best_draw[t] = od;
      }
    }
  }
  barrier();
  if (best_draw[0] < 0 || best_score[0] < 0.0) {
    if (t == 0u) regions[field(l, kDone)] = 1u;
    return;
  }
  vec3 a = scores[l * push.draws + best_draw[0]].xyz;
  // Its inliers.
  float inliers = 0.0;
  for (uint i = t; i < count; i += kThreads)
    inliers += is_inlier(a, sample_[base + int(list[i])]) ? 1.0 : 0.0;
  sums[t][0] = inliers;
  reduce_sums();
  if (int(sums[0][0] + 0.5) < needed) {
    if (t == 0u) regions[field(l, kDone)] = 1u;
    return;
  }
  for (int refit = 0; refit < 3; ++refit) {
    barrier();
    float m[9] = float[9](0, 0, 0, 0, 0, 0, 0, 0, 0);
    for (uint i = t; i < count; i += kThreads) {
      const vec4 s = sample_[base + int(list[i])];
      if (!is_inlier(a, s)) continue;
      // The normal equations' upper triangle (row-major), then the right-hand side.
      m[0] += s.x * s.x;
      m[1] += s.x * s.y;
      m[2] += s.x * s.z;
      m[3] += s.y * s.y;
      m[4] += s.y * s.z;
      m[5] += s.z * s.z;
      m[6] += s.x * s.w;
      m[7] += s.y * s.w;
      m[8] += s.z * s.w;
    }
    for (int k = 0; k < 9; ++k) sums[t][k] = m[k];
    reduce_sums();
    vec3 next;
    const bool ok = solve3(vec3(sums[0][0], sums[0][1], sums[0][2]),
                           vec3(sums[0][1], sums[0][3], sums[0][4]),
                           vec3(sums[0][2], sums[0][4], sums[0][5]),
                           vec3(sums[0][6], sums[0][7], sums[0][8]), 0.0, next);
    if (!ok) break;
    a = next;
  }
  // Tag the inliers, keep the rest in order: each thread takes kPerThread consecutive entries.
  barrier();
  const uint first = t * kPerThread;
  uint keep = 0u;
  for (uint i = first; i < min(count, first + kPerThread); ++i)
    if (!is_inlier(a, sample_[base + int(list[i])])) ++keep;
  kept[t] = keep;
  for (uint step = 1u; step < kThreads; step <<= 1) {
    barrier();
    const uint add = t >= step ? kept[t - step] : 0u;
    barrier();
    kept[t] += add;
  }
  barrier();
  uint at = kept[t] - keep;
  for (uint i = first; i < min(count, first + kPerThread); ++i) {
    const uint j = list[i];
    if (is_inlier(a, sample_[base + int(j)]))
      tags[base + int(j)] = push.plane;
    else
      alive[base + int(at++)] = j;
  }
  if (t == 0u) {
    planes[l * kMaxPlanes + push.plane] = vec4(a, 1.0);
    regions[field(l, kPlanes)] = uint(push.plane + 1);
    regions[field(l, kAlive)] = kept[kThreads - 1u];
  }
}
