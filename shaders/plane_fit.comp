#version 450
#extension GL_GOOGLE_include_directive : require
// Plane fill, first pass (server/stitch/plane_fill.h, docs/accuracy.md): one plane per cell of
// kCell x kCell panorama pixels that holds a pixel to fill (less confident than `fill_below`). A
// plane seen from the viewpoint has an inverse distance linear in the unit ray, 1/d = a . r, so
// the model is v = a . (r - r_0) + b around the cell's first pixel (r_0), fitted by weighted
// least squares over (2 taps + 1)^2 pixels `step` apart whose confidence is at least `support`,
// each weighted by its confidence, its colour's closeness to the mean colour of the cell's pixels
// to fill (sigma_c, 8-bit levels) and a spatial Gaussian (the table's), with a ridge `lambda` x
// the weights' sum on a; then `refits` fits more, each also weighting the taps by
// exp(-r^2 / 2 tau^2), r a tap's inverse-distance residual from the last plane. `planes` gets
// (a, b) per cell, b = 0 where there is none (nothing to fill, no support). plane_fill.comp then
// fills the pixels. plane_fill_cpu is the CPU check: keep the two in step.
layout(local_size_x_id = 100, local_size_y_id = 101, local_size_z_id = 102) in;

#include "pixels.glsl"

layout(std430, set = 0, binding = 0) readonly buffer Colour { uint colour[]; };
layout(std430, set = 0, binding = 1) readonly buffer DistanceIn { float distance_in[]; };
layout(std430, set = 0, binding = 2) readonly buffer Confidence { float confidence[]; };
layout(std430, set = 0, binding = 3) readonly buffer Table { vec2 table[]; };
layout(std430, set = 0, binding = 4) writeonly buffer Planes { vec4 planes[]; };
#include "plane_fill.glsl"

// The weighted least-squares plane around p0 (its ray r0) for the colour ci into s; with
// `robust`, each tap's weight also falls with its distance from `prior`'s plane (tau, m^-1).
// False where there is no support or the system is singular.
bool fit(vec3 ci, ivec2 p0, vec3 r0, vec4 prior, bool robust, out vec4 s) {
  const int w = int(push.width), h = int(push.height);
  s = vec4(0.0);
  // The normal equations (symmetric) and their right-hand side.
  mat4 m = mat4(0.0);
  vec4 rhs = vec4(0.0);
  float wsum = 0.0;
  const float colour_scale = 1.0 / (2.0 * push.sigma_c * push.sigma_c);
  const float residual_scale = robust ? 1.0 / (2.0 * push.tau * push.tau) : 0.0;
  for (int ty = -push.taps; ty <= push.taps; ++ty) {
    const int y = p0.y + ty * push.step;
    if (y < 0 || y >= h) continue;
    const float wy = spatial(ty);
    for (int tx = -push.taps; tx <= push.taps; ++tx) {
      int x = p0.x + tx * push.step;
      x = x < 0 ? x + w : (x >= w ? x - w : x);
      const uint j = uint(y * w + x);
      const float dj = distance_in[j];
      const float cj = confidence[j];
      if (!(dj > 0.0) || cj < push.support) continue;
      const vec3 dc = ci - unpack_rgb(colour[j]);
      const vec4 u = vec4(ray(x, y) - r0, 1.0);
      const float res = 1.0 / dj - dot(prior, u);
      const float wt = cj * exp(-dot(dc, dc) * colour_scale - res * res * residual_scale) *
                       (wy * spatial(tx));
      const vec4 wu = wt * u;
      m += outerProduct(u, wu);  // m[c][r] += u[r] wu[c]
      rhs += wu * (1.0 / dj);
      wsum += wt;
    }
  }
  if (!(wsum > 1e-6)) return false;
  for (int r = 0; r < 3; ++r) m[r][r] += push.lambda * wsum;
  // Cholesky m = L L^T (l[c][r] holds L's row r, column c), then L z = rhs, L^T s = z.
  mat4 l = mat4(0.0);
  vec4 z = vec4(0.0);
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c <= r; ++c) {
      float t = m[c][r];
      for (int k = 0; k < c; ++k) t -= l[k][r] * l[k][c];
      if (c == r) {
        if (!(t > 0.0)) return false;
        l[r][r] = sqrt(t);
      } else {
        l[c][r] = t / l[c][c];
      }
    }
    float t = rhs[r];
    for (int k = 0; k < r; ++k) t -= l[k][r] * z[k];
    z[r] = t / l[r][r];
  }
  for (int r = 3; r >= 0; --r) {
    float t = z[r];
    for (int k = r + 1; k < 4; ++k) t -= l[r][k] * s[k];
    s[r] = t / l[r][r];
  }
  return s.w > 0.0 && !isinf(s.w);
}

void main() {
  const int w = int(push.width), h = int(push.height);
  const int cells_x = (w + kCell - 1) / kCell;
  const ivec2 cell = ivec2(gl_GlobalInvocationID.xy);
  const ivec2 p0 = cell * kCell;
  if (p0.x >= w || p0.y >= h) return;
  const uint c = uint(cell.y * cells_x + cell.x);
  planes[c] = vec4(0.0);
  vec3 colour_sum = vec3(0.0);
  int targets = 0;
  for (int oy = 0; oy < kCell; ++oy) {
    for (int ox = 0; ox < kCell; ++ox) {
      const ivec2 p = p0 + ivec2(ox, oy);
      if (p.x >= w || p.y >= h) continue;
      const uint i = uint(p.y * w + p.x);
      if (to_fill(i)) {
        colour_sum += unpack_rgb(colour[i]);
        ++targets;
      }
    }
  }
  if (targets == 0) return;
  const vec3 ci = colour_sum / float(targets);
  const vec3 r0 = ray(p0.x, p0.y);
  vec4 s = vec4(0.0);
  if (!fit(ci, p0, r0, vec4(0.0), false, s)) return;
  // Refits against the last plane: support far from it (another surface of like colour) counts
  // less each time.
  for (int k = 0; k < push.refits; ++k) {
    vec4 next;
    if (!fit(ci, p0, r0, s, true, next)) break;
    s = next;
  }
  planes[c] = s;
}
