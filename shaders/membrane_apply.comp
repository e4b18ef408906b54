#version 450
#extension GL_GOOGLE_include_directive : require
// Membrane fill, step 4 (server/stitch/membrane_fill.h): each pixel with a distance and a
// confidence below fill_below, in a cell to fill, takes the field interpolated bilinearly
// between the cells' centres (wrapping left to right, clamped at the poles), clamped to the
// sweep's range.
layout(local_size_x_id = 100, local_size_y_id = 101, local_size_z_id = 102) in;

layout(std430, set = 0, binding = 0) buffer Distance { float distance[]; };
layout(std430, set = 0, binding = 1) readonly buffer Confidence { float confidence[]; };
layout(std430, set = 0, binding = 2) readonly buffer Value { float value[]; };
layout(std430, set = 0, binding = 3) readonly buffer Kind { uint kind[]; };
#include "membrane_fill.glsl"

float field_at(int i, int j) { return value[i * push.w + ((j % push.w) + push.w) % push.w]; }

void main() {
  const ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (p.x >= int(push.width) || p.y >= int(push.height)) return;
  const int c = push.cell, w = push.w, h = push.h;
  const uint i = uint(p.y * int(push.width) + p.x);
  if (kind[(p.y / c) * w + p.x / c] != kFill || !(distance[i] > 0.0) ||
      confidence[i] >= push.fill_below)
    return;
  const float fy = clamp((float(p.y) + 0.5) / float(c) - 0.5, 0.0, float(h - 1));
  const float fx = (float(p.x) + 0.5) / float(c) - 0.5;
  const int y0 = min(int(fy), max(h - 2, 0));
  const int y1 = min(y0 + 1, h - 1);
  const float ay = fy - float(y0);
  const int x0 = int(floor(fx));
  const float ax = fx - float(x0);
  const float field = (1.0 - ay) * ((1.0 - ax) * field_at(y0, x0) + ax * field_at(y0, x0 + 1)) +
                      ay * ((1.0 - ax) * field_at(y1, x0) + ax * field_at(y1, x0 + 1));
  distance[i] = 1.0 / clamp(field, push.inv_d_max, push.inv_d_min);
}
