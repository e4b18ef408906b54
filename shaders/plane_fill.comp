#version 450
#extension GL_GOOGLE_include_directive : require
// Plane fill (server/stitch/plane_fill.h, docs/accuracy.md): where the panorama's confidence is
// below `fill_below`, the inverse distance becomes that of a plane fitted to the confident pixels
// around it. A plane seen from the viewpoint has an inverse distance linear in the unit ray,
// 1/d = a . r, so the model is v = a . (r - r_0) + b. One invocation per cell of kCell x kCell
// pixels: where any of its pixels is to be filled, the plane is fitted around the cell's first
// pixel (r_0) by weighted least squares over (2 taps + 1)^2 pixels `step` apart whose
// confidence is at least `support`, each weighted by its confidence, its colour's closeness to
// the mean colour of the cell's pixels to fill (sigma_c, 8-bit levels) and its distance (a
// Gaussian of sigma_s pixels), with a ridge `lambda` x the weights' sum on a (no support: no
// change). Each pixel to fill gets the plane at its own ray, clamped to the sweep's range. The
// rays and the spatial weights come from a table the host fills once (`table`: per column cos
// and sin of the longitude, per row sin and cos of the colatitude, then the weight for tap
// offsets -taps .. taps). plane_fill_cpu is the CPU check: keep the two in step.
layout(local_size_x_id = 100, local_size_y_id = 101, local_size_z_id = 102) in;

#include "pixels.glsl"

layout(std430, set = 0, binding = 0) readonly buffer Colour { uint colour[]; };
layout(std430, set = 0, binding = 1) readonly buffer DistanceIn { float distance_in[]; };
layout(std430, set = 0, binding = 2) readonly buffer Confidence { float confidence[]; };
layout(std430, set = 0, binding = 3) readonly buffer Table { vec2 table[]; };
layout(std430, set = 0, binding = 4) writeonly buffer DistanceOut { float distance_out[]; };
layout(push_constant) uniform Push {
  uint width;
  uint height;
  int step;
  int taps;
  float fill_below;
  float support;
  float sigma_c;
  float lambda;
  float inv_d_min;
  float inv_d_max;
} push;

vec3 ray(int x, int y) {
  const vec2 longitude = table[x];
  const vec2 colatitude = table[int(push.width) + y];
  return vec3(colatitude.x * longitude.x, colatitude.x * longitude.y, colatitude.y);
}

float spatial(int t) { return table[int(push.width + push.height) + t + push.taps].x; }

const int kCell = 4;

// Pixel i is one to fill.
bool to_fill(uint i) {
  const float d = distance_in[i];
  return d > 0.0 && confidence[i] < push.fill_below;
}

void main() {
  const int w = int(push.width), h = int(push.height);
  const ivec2 p0 = ivec2(gl_GlobalInvocationID.xy) * kCell;
  if (p0.x >= w || p0.y >= h) return;
  vec3 colour_sum = vec3(0.0);
  int targets = 0;
  for (int oy = 0; oy < kCell; ++oy) {
    for (int ox = 0; ox < kCell; ++ox) {
      const ivec2 p = p0 + ivec2(ox, oy);
      if (p.x >= w || p.y >= h) continue;
      const uint i = uint(p.y * w + p.x);
      distance_out[i] = distance_in[i];
      if (to_fill(i)) {
        colour_sum += unpack_rgb(colour[i]);
        ++targets;
      }
    }
  }
  if (targets == 0) return;
  const vec3 ci = colour_sum / float(targets);
  const vec3 r0 = ray(p0.x, p0.y);
  // The normal equations (symmetric) and their right-hand side.
  mat4 m = mat4(0.0);
  vec4 rhs = vec4(0.0);
  float wsum = 0.0;
  const float colour_scale = 1.0 / (2.0 * push.sigma_c * push.sigma_c);
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
      const float wt = cj * exp(-dot(dc, dc) * colour_scale) * (wy * spatial(tx));
      const vec4 u = vec4(ray(x, y) - r0, 1.0);
      const vec4 wu = wt * u;
      m += outerProduct(u, wu);  // m[c][r] += u[r] wu[c]
      rhs += wu * (1.0 / dj);
      wsum += wt;
    }
  }
  if (!(wsum > 1e-6)) return;
  for (int r = 0; r < 3; ++r) m[r][r] += push.lambda * wsum;
  // Cholesky m = L L^T (l[c][r] holds L's row r, column c), then L z = rhs, L^T s = z.
  mat4 l = mat4(0.0);
  vec4 z = vec4(0.0);
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c <= r; ++c) {
      float t = m[c][r];
      for (int k = 0; k < c; ++k) t -= l[k][r] * l[k][c];
      if (c == r) {
        if (!(t > 0.0)) return;
        l[r][r] = sqrt(t);
      } else {
        l[c][r] = t / l[c][c];
      }
    }
    float t = rhs[r];
    for (int k = 0; k < r; ++k) t -= l[k][r] * z[k];
    z[r] = t / l[r][r];
  }
  vec4 s = vec4(0.0);
  for (int r = 3; r >= 0; --r) {
    float t = z[r];
    for (int k = r + 1; k < 4; ++k) t -= l[r][k] * s[k];
    s[r] = t / l[r][r];
  }
  for (int oy = 0; oy < kCell; ++oy) {
    for (int ox = 0; ox < kCell; ++ox) {
      const ivec2 p = p0 + ivec2(ox, oy);
      if (p.x >= w || p.y >= h) continue;
      const uint i = uint(p.y * w + p.x);
      if (!to_fill(i)) continue;
      const float v = s.w + dot(s.xyz, ray(p.x, p.y) - r0);
      if (v > 0.0 && !isinf(v)) distance_out[i] = 1.0 / clamp(v, push.inv_d_max, push.inv_d_min);
    }
  }
}
