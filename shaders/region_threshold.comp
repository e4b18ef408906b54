#version 450
#extension GL_GOOGLE_include_directive : require
// Region planes, step 3b (server/stitch/region_planes.h): per region (one invocation each), its
// supports (the histogram's sum) and the last of its 256 hash bins whose supports together are
// at most kCandidates (-1 if the first alone is more): those bins' supports are the candidates
// its sample is sorted from.
layout(local_size_x_id = 100, local_size_y_id = 101, local_size_z_id = 102) in;

layout(std430, set = 0, binding = 0) buffer Regions { uint regions[]; };
layout(std430, set = 0, binding = 1) readonly buffer Histogram { uint histogram[]; };
#include "region_planes.glsl"

void main() {
  const int l = int(gl_GlobalInvocationID.x);
  if (l >= int(regions[0])) return;
  uint sum = 0u, total = 0u;
  int last = -1;
  for (int t = 0; t < 256; ++t) {
    const uint n = histogram[l * 256 + t];
    total += n;
    if (last == t - 1 && sum + n <= uint(kCandidates)) {
      sum += n;
      last = t;
    }
  }
  regions[field(l, kSupports)] = total;
  regions[field(l, kLastBin)] = uint(last);
  regions[field(l, kCollected)] = 0u;
}
