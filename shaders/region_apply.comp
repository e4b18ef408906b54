#version 450
#extension GL_GOOGLE_include_directive : require
// Region planes, step 6 (server/stitch/region_planes.h): each unconfident pixel (a distance,
// confidence < fill_below) of a block that planes surround takes the one nearest its own inverse
// distance, mixed with it by alpha = 1 - confidence / fill_below and clamped to the sweep's
// range; in place, other pixels untouched.
layout(local_size_x_id = 100, local_size_y_id = 101, local_size_z_id = 102) in;

layout(std430, set = 0, binding = 0) buffer Distance { float distance[]; };
layout(std430, set = 0, binding = 1) readonly buffer Confidence { float confidence[]; };
layout(std430, set = 0, binding = 2) readonly buffer Table { vec2 table[]; };
layout(std430, set = 0, binding = 3) readonly buffer Planes { vec4 planes[]; };
layout(std430, set = 0, binding = 4) readonly buffer Surround { uvec2 surround[]; };
#define REGION_RAYS
#include "region_planes.glsl"

void main() {
  const ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  const int w = int(push.width), h = int(push.height);
  if (p.x >= w || p.y >= h) return;
  const uvec2 s = surround[(p.y / push.block) * push.blocks_x + p.x / push.block];
  if (s.x == 0u) return;
  const uint i = uint(p.y * w + p.x);
  const float d = distance[i], c = confidence[i];
  if (!(d > 0.0) || !(c < push.fill_below)) return;
  const vec3 r = ray(p.x, p.y);
  const float own = 1.0 / d;
  float pick = 0.0, nearest = 1.0 / 0.0;
  for (int k = 0; k < kMaxPlanes; ++k) {
    if ((s.x & (1u << k)) == 0u) continue;
    const float pv = dot(planes[int(s.y) * kMaxPlanes + k].xyz, r);
    if (pv > 0.0 && abs(pv - own) < nearest) {
      nearest = abs(pv - own);
      pick = pv;
    }
  }
  if (!(pick > 0.0)) return;
  const float alpha = 1.0 - c / push.fill_below;
  distance[i] = 1.0 / clamp(alpha * pick + (1.0 - alpha) * own, push.inv_d_max, push.inv_d_min);
}
