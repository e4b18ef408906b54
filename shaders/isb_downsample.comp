#version 450
#extension GL_GOOGLE_include_directive : require
#ifdef VOLUME_F16
#extension GL_EXT_shader_16bit_storage : require
#endif
// Inter-scale bilateral filter, down pass (ALGORITHM.md §4): coarse pixel (x, y) gathers the
// 3x3 neighbourhood of fine pixel (2x, 2y) (indices clamped) with spatial weights 1 / 0.5 / 0.25
// (centre / edge / corner), each off-centre weight times exp(-g^2 / (2 sigma_I^2)) + 0.01. The
// coarse guide (rounded to 8 bits) and every channel are the normalised weighted sums. z is the
// slot (volume.glsl); the fine guide of slot z is plane fine_guide_first + z of its buffer.
// With kConfidentSigma the guide's fourth byte (isb_weights.glsl) is averaged with the same
// weights; otherwise the coarse guide's fourth byte is 0.
layout(local_size_x_id = 100, local_size_y_id = 101, local_size_z_id = 102) in;

#include "pixels.glsl"
#include "isb_weights.glsl"
#include "volume.glsl"

layout(constant_id = 3) const bool kConfidentSigma = false;

layout(set = 0, binding = 0) uniform usamplerBuffer fine_guide;
layout(std430, set = 0, binding = 1) writeonly buffer CoarseGuide { uint coarse_guide[]; };
layout(set = 0, binding = 2) uniform samplerBuffer fine[kMaxChunks];
layout(std430, set = 0, binding = 3) writeonly buffer Coarse { VOLUME_T v[]; } coarse[kMaxChunks];
layout(push_constant) uniform Push {
  uint fine_width;
  uint fine_height;
  uint coarse_width;
  uint coarse_height;
  float inv_two_sigma_sq;
  uint fine_guide_first;
} push;

// Fine pixel n(dx, dy) of the 3x3 block around (2x, 2y) is nb (dy + 1) * 3 + dx + 1, summed in
// that order. Written out with scalars (no arrays): a CPU device keeps arrays indexed in loops
// in memory, per lane.
#define DOWN_WEIGHT(g, s) ((s) * range_weight(centre_guide, g, push.inv_two_sigma_sq))

void main() {
  const uvec3 p = gl_GlobalInvocationID;
  if (p.x >= push.coarse_width || p.y >= push.coarse_height) return;
  const uint slot = p.z;
  const uint fine_plane = push.fine_width * push.fine_height;
  const uint coarse_plane = push.coarse_width * push.coarse_height;
  const int guide_base = int((push.fine_guide_first + slot) * fine_plane);
  const int fw = int(push.fine_width);
  const int cx = 2 * int(p.x), cy = 2 * int(p.y);
  const int x0 = max(cx - 1, 0), x1 = min(cx, fw - 1), x2 = min(cx + 1, fw - 1);
  const int y0 = max(cy - 1, 0), y1 = min(cy, int(push.fine_height) - 1),
            y2 = min(cy + 1, int(push.fine_height) - 1);
  const int i0 = y0 * fw + x0, i1 = y0 * fw + x1, i2 = y0 * fw + x2;
  const int i3 = y1 * fw + x0, i4 = y1 * fw + x1, i5 = y1 * fw + x2;
  const int i6 = y2 * fw + x0, i7 = y2 * fw + x1, i8 = y2 * fw + x2;
  const uint g0 = texelFetch(fine_guide, guide_base + i0).x, g1 = texelFetch(fine_guide, guide_base + i1).x,
             g2 = texelFetch(fine_guide, guide_base + i2).x, g3 = texelFetch(fine_guide, guide_base + i3).x,
             g4 = texelFetch(fine_guide, guide_base + i4).x, g5 = texelFetch(fine_guide, guide_base + i5).x,
             g6 = texelFetch(fine_guide, guide_base + i6).x, g7 = texelFetch(fine_guide, guide_base + i7).x,
             g8 = texelFetch(fine_guide, guide_base + i8).x;
  const uint centre_guide = g4;
  const float w0 = DOWN_WEIGHT(g0, 0.25), w1 = DOWN_WEIGHT(g1, 0.5), w2 = DOWN_WEIGHT(g2, 0.25),
              w3 = DOWN_WEIGHT(g3, 0.5), w4 = 1.0, w5 = DOWN_WEIGHT(g5, 0.5),
              w6 = DOWN_WEIGHT(g6, 0.25), w7 = DOWN_WEIGHT(g7, 0.5), w8 = DOWN_WEIGHT(g8, 0.25);
  float total = 0.0;
  vec3 guide_sum = vec3(0.0);
  float confidence_sum = 0.0;
#define DOWN_ADD(w, g)                                        \
  total += w;                                                 \
  guide_sum += w * unpack_rgb(g);                             \
  if (kConfidentSigma) confidence_sum += w * float(g >> 24u);
  DOWN_ADD(w0, g0) DOWN_ADD(w1, g1) DOWN_ADD(w2, g2) DOWN_ADD(w3, g3) DOWN_ADD(w4, g4)
  DOWN_ADD(w5, g5) DOWN_ADD(w6, g6) DOWN_ADD(w7, g7) DOWN_ADD(w8, g8)
  const uint out_index = p.y * push.coarse_width + p.x;
  const uint confidence =
      kConfidentSigma ? uint(clamp(floor(confidence_sum / total + 0.5), 0.0, 255.0)) << 24u : 0u;
  coarse_guide[slot * coarse_plane + out_index] = round_guide(guide_sum / total) | confidence;
  const float inv_total = 1.0 / total;
// Every channel of chunk c (a literal: texel arrays take constant indices, volume.glsl).
#define DOWN_CHUNK(c)                                                                          \
  if (uint(c) < kChunks) {                                                                     \
    for (uint t = 0u; t < kTexels; ++t) {                                                      \
      const int b = int(volume_index(slot, t, fine_plane, 0u));                                \
      VOLUME_V sum = VOLUME_V(0.0);                                                            \
      sum += w0 * VOLUME_FETCH(fine[c], b + i0); sum += w1 * VOLUME_FETCH(fine[c], b + i1);    \
      sum += w2 * VOLUME_FETCH(fine[c], b + i2); sum += w3 * VOLUME_FETCH(fine[c], b + i3);    \
      sum += w4 * VOLUME_FETCH(fine[c], b + i4); sum += w5 * VOLUME_FETCH(fine[c], b + i5);    \
      sum += w6 * VOLUME_FETCH(fine[c], b + i6); sum += w7 * VOLUME_FETCH(fine[c], b + i7);    \
      sum += w8 * VOLUME_FETCH(fine[c], b + i8);                                               \
      coarse[c].v[volume_index(slot, t, coarse_plane, out_index)] = VOLUME_T(sum * inv_total); \
    }                                                                                          \
  }
  FOR_EACH_CHUNK(DOWN_CHUNK)
}
