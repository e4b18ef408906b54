#version 450
#extension GL_GOOGLE_include_directive : require
// Region planes, step 4 (server/stitch/region_planes.h): one dispatch per plane of the sequential
// RANSAC, push.plane = k from 0 to max_planes, with draws / 256 workgroups per region (rounded
// up), each scoring its share of the draws. Dispatch k first concludes plane k - 1 from the
// previous dispatch's scores: the best draw (the highest score, the first of equals), unless it
// has too few inliers (then the region is done), refitted three times by least squares on its
// inliers (Cramer's rule on the normal equations), its inliers taken off the alive list, which
// keeps its order. Every workgroup of the region does this, the same arithmetic on the same data
// (so the scoring needs no second dispatch); the first also tags the inliers with the plane and
// writes it out. Then, unless k = max_planes, each of its invocations scores one draw of plane k:
// the plane through three alive supports drawn by draw_hash, MSAC over every alive support in
// order (-1 where the three are degenerate). Plane k's alive list and scores live in half k % 2
// of their buffers, so a dispatch reads one half and writes the other. region_planes_cpu is the
// CPU check.
layout(local_size_x_id = 100, local_size_y_id = 101, local_size_z_id = 102) in;

layout(std430, set = 0, binding = 0) buffer Regions { uint regions[]; };
layout(std430, set = 0, binding = 1) readonly buffer Sample { vec4 sample_[]; };
layout(std430, set = 0, binding = 2) buffer Alive { uint alive[]; };  // two halves
layout(std430, set = 0, binding = 3) writeonly buffer Tags { int tags[]; };
layout(std430, set = 0, binding = 4) buffer Scores { vec4 scores[]; };  // two halves
layout(std430, set = 0, binding = 5) writeonly buffer Planes { vec4 planes[]; };
#include "region_planes.glsl"

const uint kThreads = 256u;  // the workgroup (set by the host): draws per workgroup
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

// Plane k's alive list and its count: the first list is region_sample.comp's.
int alive_base(int l, int k) { return ((k & 1) * push.max_regions + l) * kSample; }
int count_field(int k) { return (k & 1) == 0 ? kAlive : kAliveOdd; }
int scores_base(int l, int k) { return ((k & 1) * push.max_regions + l) * push.draws; }

void main() {
  const int l = int(gl_WorkGroupID.y);
  const uint t = gl_LocalInvocationID.x;
  const int k = push.plane;
  if (l >= int(regions[0]) || regions[field(l, kDone)] != 0u) return;
  const bool first_group = gl_WorkGroupID.x == 0u;
  const int base = l * kSample;
  const int needed = needed_inliers(int(regions[field(l, kSampled)]), regions[field(l, kSupports)]);
  // The alive list the previous plane was scored on (plane 0: region_sample.comp's).
  const int from = max(k - 1, 0);
  uint count = regions[field(l, count_field(from))];
  for (uint i = t; i < count; i += kThreads) list[i] = alive[alive_base(l, from) + int(i)];
  if (k > 0) {
    // Plane k - 1: the best draw.
    float best = -1.0;
    int pick = -1;
    const int sb = scores_base(l, k - 1);
    for (int d = int(t); d < push.draws; d += int(kThreads)) {
      const float s = scores[sb + d].w;
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
      if (first_group && t == 0u) regions[field(l, kDone)] = 1u;
      return;
    }
    vec3 a = scores[sb + best_draw[0]].xyz;
    // Its inliers.
    float inliers = 0.0;
    for (uint i = t; i < count; i += kThreads)
      inliers += is_inlier(a, sample_[base + int(list[i])]) ? 1.0 : 0.0;
    sums[t][0] = inliers;
    reduce_sums();
    if (int(sums[0][0] + 0.5) < needed) {
      if (first_group && t == 0u) regions[field(l, kDone)] = 1u;
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
      for (int q = 0; q < 9; ++q) sums[t][q] = m[q];
      reduce_sums();
      vec3 next;
      const bool ok = solve3(vec3(sums[0][0], sums[0][1], sums[0][2]),
                             vec3(sums[0][1], sums[0][3], sums[0][4]),
                             vec3(sums[0][2], sums[0][4], sums[0][5]),
                             vec3(sums[0][6], sums[0][7], sums[0][8]), 0.0, next);
      if (!ok) break;
      a = next;
    }
    // Tag the inliers, keep the rest in order: each invocation takes kPerThread consecutive
    // entries, all read before any is moved.
    const uint first = t * kPerThread;
    uint mine[kPerThread];
    bool inlier[kPerThread];
    uint keep = 0u;
    for (uint q = 0u; q < kPerThread; ++q) {
      const uint i = first + q;
      mine[q] = i < count ? list[i] : kNone;
      inlier[q] = i < count && is_inlier(a, sample_[base + int(mine[q])]);
      if (i < count && !inlier[q]) ++keep;
    }
    kept[t] = keep;
    for (uint step = 1u; step < kThreads; step <<= 1) {
      barrier();
      const uint add = t >= step ? kept[t - step] : 0u;
      barrier();
      kept[t] += add;
    }
    barrier();
    uint at = kept[t] - keep;
    for (uint q = 0u; q < kPerThread; ++q) {
      if (first + q >= count) break;
      if (!inlier[q]) {
        list[at] = mine[q];
        if (first_group) alive[alive_base(l, k) + int(at)] = mine[q];
        ++at;
      } else if (first_group) {
        tags[base + int(mine[q])] = k - 1;
      }
    }
    count = kept[kThreads - 1u];
    if (first_group && t == 0u) {
      planes[l * kMaxPlanes + k - 1] = vec4(a, 1.0);
      regions[field(l, kPlanes)] = uint(k);
      regions[field(l, count_field(k))] = count;
    }
  }
  if (k >= push.max_planes) return;
  if (int(count) < needed || count < 3u) {
    if (first_group && t == 0u) regions[field(l, kDone)] = 1u;
    return;
  }
  barrier();  // the list is complete
  // Plane k: this invocation's draw.
  const int d = int(gl_WorkGroupID.x * kThreads + t);
  if (d >= push.draws) return;
  const uint root = regions[field(l, kRoot)];
  vec4 s[3];
  for (int q = 0; q < 3; ++q)
    s[q] = sample_[base + int(list[draw_hash(root, uint(k), uint(3 * d + q)) % count])];
  vec3 a;
  float score = -1.0;
  if (solve3(s[0].xyz, s[1].xyz, s[2].xyz, vec3(s[0].w, s[1].w, s[2].w), 1e-6, a)) {
    score = 0.0;
    for (uint i = 0u; i < count; ++i) score += msac(a, sample_[base + int(list[i])]);
  }
  scores[scores_base(l, k) + d] = vec4(a, score);
}
