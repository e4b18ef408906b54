#version 450
#extension GL_GOOGLE_include_directive : require
// Plane fill, second pass (server/stitch/plane_fill.h, docs/accuracy.md): each pixel to fill
// (a distance less confident than `fill_below`) gets the planes of plane_fit.comp's four cells
// whose centres surround it, evaluated at its own ray and blended bilinearly (cells without a
// plane left out, so no cell grid shows), then mixed with its own inverse distance by
// alpha = 1 - confidence / fill_below (no step where the confidence crosses the threshold) and
// clamped to the sweep's range. Other pixels are copied. plane_fill_cpu is the CPU check: keep
// the two in step.
layout(local_size_x_id = 100, local_size_y_id = 101, local_size_z_id = 102) in;

layout(std430, set = 0, binding = 0) readonly buffer DistanceIn { float distance_in[]; };
layout(std430, set = 0, binding = 1) readonly buffer Confidence { float confidence[]; };
layout(std430, set = 0, binding = 2) readonly buffer Table { vec2 table[]; };
layout(std430, set = 0, binding = 3) readonly buffer Planes { vec4 planes[]; };
layout(std430, set = 0, binding = 4) writeonly buffer DistanceOut { float distance_out[]; };
#include "plane_fill.glsl"

void main() {
  const ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  const int w = int(push.width), h = int(push.height);
  if (p.x >= w || p.y >= h) return;
  const uint i = uint(p.y * w + p.x);
  const float d = distance_in[i];
  distance_out[i] = d;
  if (!to_fill(i)) return;
  const int cells_x = (w + kCell - 1) / kCell, cells_y = (h + kCell - 1) / kCell;
  // The cells whose centres surround p, and p's place between them.
  const vec2 f = (vec2(p) - vec2(0.5 * float(kCell - 1))) / float(kCell);
  const ivec2 c0 = ivec2(floor(f));
  const vec2 t = f - vec2(c0);
  const vec3 rp = ray(p.x, p.y);
  float v = 0.0, wsum = 0.0;
  for (int dy = 0; dy < 2; ++dy) {
    const int cy = clamp(c0.y + dy, 0, cells_y - 1);
    const float wy = dy == 0 ? 1.0 - t.y : t.y;
    for (int dx = 0; dx < 2; ++dx) {
      int cx = c0.x + dx;
      cx = cx < 0 ? cx + cells_x : (cx >= cells_x ? cx - cells_x : cx);
      const float weight = wy * (dx == 0 ? 1.0 - t.x : t.x);
      const vec4 s = planes[cy * cells_x + cx];
      if (!(s.w > 0.0) || !(weight > 0.0)) continue;
      v += weight * (s.w + dot(s.xyz, rp - ray(cx * kCell, cy * kCell)));
      wsum += weight;
    }
  }
  if (!(wsum > 0.0)) return;
  const float alpha = 1.0 - confidence[i] / push.fill_below;
  v = alpha * (v / wsum) + (1.0 - alpha) * (1.0 / d);
  if (v > 0.0 && !isinf(v)) distance_out[i] = 1.0 / clamp(v, push.inv_d_max, push.inv_d_min);
}
