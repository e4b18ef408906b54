#version 450
#extension GL_GOOGLE_include_directive : require
// Edge check, first pass (server/stitch/edge_check.h, docs/accuracy.md): one invocation per
// block marks it (1) where one of its pixels, within 3 x 3 pixels (columns wrapping, rows
// clamped, pixels without a distance left out), sees its inverse distance change by more than
// `step` while no colour channel changes by `color` levels or more: a distance carried across a
// plain surface. edge_check_cpu is the CPU check: keep the two in step.
layout(local_size_x_id = 100, local_size_y_id = 101, local_size_z_id = 102) in;

layout(std430, set = 0, binding = 0) readonly buffer Color { uint color[]; };
layout(std430, set = 0, binding = 1) readonly buffer Distance { float distance[]; };
layout(std430, set = 0, binding = 2) writeonly buffer Marks { uint marks[]; };
#include "edge_check.glsl"

bool carried(int x, int y) {
  const int w = int(push.width), h = int(push.height);
  float lo = 1e30, hi = -1e30;
  vec3 clo = vec3(1e30), chi = vec3(-1e30);
  for (int dy = -1; dy <= 1; ++dy) {
    const int yy = y + dy;
    if (yy < 0 || yy >= h) continue;
    for (int dx = -1; dx <= 1; ++dx) {
      const int xx = (x + dx + w) % w;
      const uint i = uint(yy * w + xx);
      const float d = distance[i];
      if (!(d > 0.0)) continue;
      const float v = 1.0 / d;
      lo = min(lo, v);
      hi = max(hi, v);
      const uint c = color[i];
      const vec3 rgb = vec3(float(c & 255u), float((c >> 8) & 255u), float((c >> 16) & 255u));
      clo = min(clo, rgb);
      chi = max(chi, rgb);
    }
  }
  const vec3 range = chi - clo;
  return hi - lo > push.step && max(range.r, max(range.g, range.b)) < push.color;
}

void main() {
  const ivec2 b = ivec2(gl_GlobalInvocationID.xy);
  if (b.x >= blocks_x() || b.y >= blocks_y()) return;
  const int w = int(push.width), h = int(push.height);
  uint mark = 0u;
  for (int y = b.y * push.block; y < min(h, (b.y + 1) * push.block) && mark == 0u; ++y) {
    for (int x = b.x * push.block; x < min(w, (b.x + 1) * push.block); ++x) {
      if (distance[uint(y * w + x)] > 0.0 && carried(x, y)) {
        mark = 1u;
        break;
      }
    }
  }
  marks[uint(b.y * blocks_x() + b.x)] = mark;
}
