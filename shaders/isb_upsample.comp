#version 450
#extension GL_GOOGLE_include_directive : require
#ifdef VOLUME_F16
#extension GL_EXT_shader_16bit_storage : require
#endif
// Inter-scale bilateral filter, up pass (ALGORITHM.md §4), in place on the fine level l: fine
// pixel f becomes (w_up f + sum_k w_k coarse_k) / (w_up + sum_k w_k), with
// w_k = w_down s_k (exp(-g_k^2 / (2 sigma_I^2)) + 0.01), w_down = exp(-(2^l - 0.5)^2 / (2 sigma_s^2)),
// w_up = 1 - w_down. The coarse neighbours and spatial weights s_k depend on which child of its
// coarse pixel (x, y) f is; coarse indices are clamped. The fine guide is updated with the same
// weights. One invocation per coarse pixel computes its four children, so each coarse value is
// fetched once for all four (13 fetches per channel for 4 pixels, not 29). Each invocation reads
// and writes only its own children, so in place is safe (it reads through texel buffers and
// writes through storage buffers bound to the same memory). Every child sums its terms in the
// order of ALGORITHM.md's neighbour lists (and the CPU reference's). z is the slot
// (volume.glsl); the fine guide of slot z is plane fine_guide_first + z of its buffer.
// With kWinnerTakesAll (the last pass of a cost volume's filter) the filtered costs are not
// stored: each pixel's winner (wta.glsl) is written to `distance_map` instead, which saves the
// winner-takes-all kernel a full read of the volume and this pass its write; slot z's distances
// are plane distance_first + z of `distance_map`, and their confidences (wta.glsl) the same plane
// of `confidence_map`.
// With kConfidentSigma each child's w_down comes from its guide's fourth byte
// (confident_w_down, isb_weights.glsl), which its smoothed guide keeps.
layout(local_size_x_id = 100, local_size_y_id = 101, local_size_z_id = 102) in;

#include "pixels.glsl"
#include "isb_weights.glsl"
#include "volume.glsl"
#include "wta.glsl"

layout(constant_id = 2) const bool kWinnerTakesAll = false;
layout(constant_id = 3) const bool kConfidentSigma = false;

layout(std430, set = 0, binding = 0) writeonly buffer FineGuide { uint fine_guide[]; };
layout(set = 0, binding = 1) uniform usamplerBuffer coarse_guide;
layout(std430, set = 0, binding = 2) writeonly buffer Fine { VOLUME_T v[]; } fine[kMaxChunks];
layout(set = 0, binding = 3) uniform samplerBuffer coarse[kMaxChunks];
layout(std430, set = 0, binding = 4) writeonly buffer Distance { float distance_map[]; };
layout(set = 0, binding = 5) uniform usamplerBuffer fine_guide_texels;  // binding 0's buffer
layout(set = 0, binding = 6) uniform samplerBuffer fine_texels[kMaxChunks];  // binding 2's
layout(std430, set = 0, binding = 7) writeonly buffer Confidence { float confidence_map[]; };
layout(push_constant) uniform Push {
  uint fine_width;
  uint fine_height;
  uint coarse_width;
  uint coarse_height;
  float inv_two_sigma_sq;
  float w_down;
  uint fine_guide_first;
  // kWinnerTakesAll only:
  uint num_candidates;
  float inv_d_min;
  float inv_d_max;
  float d_max;
  float inv_raw_agreement;  // 1 / DepthOptions::raw_agreement, 0: off
  uint distance_first;
  // kConfidentSigma only: (2^l - 0.5)^2 and the two spatial sigmas.
  float scale_sq;
  float sigma_s;
  float sigma_confident;
} push;

// The children of a coarse pixel (2x, 2y), (2x + 1, 2y), (2x, 2y + 1), (2x + 1, 2y + 1) are
// children 0-3. Coarse neighbour n(dx, dy) of the 3x3 block around the coarse pixel is nb
// (dy + 1) * 3 + dx + 1. Each child blends, in this order (ALGORITHM.md §4, spatial weight in
// brackets):
//   child 0: nb 0-8 [1, 1, 1, 1, 8, 1, 1, 1, 1]        child 1: nb 4, 5, 1, 2, 7, 8 [8, 8, 1, 1, 1, 1]
//   child 2: nb 4, 7, 3, 6, 5, 8 [8, 8, 1, 1, 1, 1]    child 3: nb 4, 5, 7, 8 [1, 1, 1, 1]
// Everything is written out with scalars (no arrays): a CPU device keeps arrays indexed in loops
// in memory, per lane, which made this pass several times slower.

// A child's weight for coarse neighbour guide g with spatial weight s.
#define UP_WEIGHT(w_down, own, g, s) ((w_down) * (s) * range_weight(own, g, push.inv_two_sigma_sq))
// Adds a neighbour's weight to a child's total and guide sum.
#define UP_ADD(child, w, g)        \
  total##child += w;               \
  guide_sum##child += w * unpack_rgb(g);

void main() {
  const uvec2 cp = gl_GlobalInvocationID.xy;
  const uint slot = gl_GlobalInvocationID.z;
  if (cp.x >= push.coarse_width || cp.y >= push.coarse_height) return;
  const uint fine_plane = push.fine_width * push.fine_height;
  const uint coarse_plane = push.coarse_width * push.coarse_height;
  const int x0 = max(int(cp.x) - 1, 0), x1 = int(cp.x), x2 = min(int(cp.x) + 1, int(push.coarse_width) - 1);
  const int y0 = max(int(cp.y) - 1, 0), y1 = int(cp.y), y2 = min(int(cp.y) + 1, int(push.coarse_height) - 1);
  const int cw = int(push.coarse_width);
  const int i0 = y0 * cw + x0, i1 = y0 * cw + x1, i2 = y0 * cw + x2;
  const int i3 = y1 * cw + x0, i4 = y1 * cw + x1, i5 = y1 * cw + x2;
  const int i6 = y2 * cw + x0, i7 = y2 * cw + x1, i8 = y2 * cw + x2;
  const int gb = int(slot * coarse_plane);
  const uint g0 = texelFetch(coarse_guide, gb + i0).x, g1 = texelFetch(coarse_guide, gb + i1).x,
             g2 = texelFetch(coarse_guide, gb + i2).x, g3 = texelFetch(coarse_guide, gb + i3).x,
             g4 = texelFetch(coarse_guide, gb + i4).x, g5 = texelFetch(coarse_guide, gb + i5).x,
             g6 = texelFetch(coarse_guide, gb + i6).x, g7 = texelFetch(coarse_guide, gb + i7).x,
             g8 = texelFetch(coarse_guide, gb + i8).x;

  // The children: inside the fine level (odd sizes leave the last column or row out), their
  // index in the plane and their own guides.
  const uvec2 f0 = 2u * cp;
  const bool right = f0.x + 1u < push.fine_width, below = f0.y + 1u < push.fine_height;
  const bool inside0 = true, inside1 = right, inside2 = below, inside3 = right && below;
  const uint fine0 = f0.y * push.fine_width + f0.x;
  const uint fine1 = right ? fine0 + 1u : fine0, fine2 = below ? fine0 + push.fine_width : fine0;
  const uint fine3 = right && below ? fine0 + push.fine_width + 1u : fine0;
  const uint guide_base = (push.fine_guide_first + slot) * fine_plane;
  const uint own0 = texelFetch(fine_guide_texels, int(guide_base + fine0)).x;
  const uint own1 = texelFetch(fine_guide_texels, int(guide_base + fine1)).x;
  const uint own2 = texelFetch(fine_guide_texels, int(guide_base + fine2)).x;
  const uint own3 = texelFetch(fine_guide_texels, int(guide_base + fine3)).x;

#define CHILD_W_DOWN(own) \
  (kConfidentSigma ? confident_w_down(own, push.scale_sq, push.sigma_s, push.sigma_confident) : push.w_down)
  const float down0 = CHILD_W_DOWN(own0), down1 = CHILD_W_DOWN(own1), down2 = CHILD_W_DOWN(own2),
              down3 = CHILD_W_DOWN(own3);
  const float up0 = 1.0 - down0, up1 = 1.0 - down1, up2 = 1.0 - down2, up3 = 1.0 - down3;
  float total0 = up0, total1 = up1, total2 = up2, total3 = up3;
  vec3 guide_sum0 = up0 * unpack_rgb(own0), guide_sum1 = up1 * unpack_rgb(own1);
  vec3 guide_sum2 = up2 * unpack_rgb(own2), guide_sum3 = up3 * unpack_rgb(own3);
  const float wa0 = UP_WEIGHT(down0, own0, g0, 1.0), wa1 = UP_WEIGHT(down0, own0, g1, 1.0), wa2 = UP_WEIGHT(down0, own0, g2, 1.0),
              wa3 = UP_WEIGHT(down0, own0, g3, 1.0), wa4 = UP_WEIGHT(down0, own0, g4, 8.0), wa5 = UP_WEIGHT(down0, own0, g5, 1.0),
              wa6 = UP_WEIGHT(down0, own0, g6, 1.0), wa7 = UP_WEIGHT(down0, own0, g7, 1.0), wa8 = UP_WEIGHT(down0, own0, g8, 1.0);
  UP_ADD(0, wa0, g0) UP_ADD(0, wa1, g1) UP_ADD(0, wa2, g2) UP_ADD(0, wa3, g3) UP_ADD(0, wa4, g4)
  UP_ADD(0, wa5, g5) UP_ADD(0, wa6, g6) UP_ADD(0, wa7, g7) UP_ADD(0, wa8, g8)
  const float wb0 = UP_WEIGHT(down1, own1, g4, 8.0), wb1 = UP_WEIGHT(down1, own1, g5, 8.0), wb2 = UP_WEIGHT(down1, own1, g1, 1.0),
              wb3 = UP_WEIGHT(down1, own1, g2, 1.0), wb4 = UP_WEIGHT(down1, own1, g7, 1.0), wb5 = UP_WEIGHT(down1, own1, g8, 1.0);
  UP_ADD(1, wb0, g4) UP_ADD(1, wb1, g5) UP_ADD(1, wb2, g1) UP_ADD(1, wb3, g2) UP_ADD(1, wb4, g7)
  UP_ADD(1, wb5, g8)
  const float wc0 = UP_WEIGHT(down2, own2, g4, 8.0), wc1 = UP_WEIGHT(down2, own2, g7, 8.0), wc2 = UP_WEIGHT(down2, own2, g3, 1.0),
              wc3 = UP_WEIGHT(down2, own2, g6, 1.0), wc4 = UP_WEIGHT(down2, own2, g5, 1.0), wc5 = UP_WEIGHT(down2, own2, g8, 1.0);
  UP_ADD(2, wc0, g4) UP_ADD(2, wc1, g7) UP_ADD(2, wc2, g3) UP_ADD(2, wc3, g6) UP_ADD(2, wc4, g5)
  UP_ADD(2, wc5, g8)
  const float wd0 = UP_WEIGHT(down3, own3, g4, 1.0), wd1 = UP_WEIGHT(down3, own3, g5, 1.0), wd2 = UP_WEIGHT(down3, own3, g7, 1.0),
              wd3 = UP_WEIGHT(down3, own3, g8, 1.0);
  UP_ADD(3, wd0, g4) UP_ADD(3, wd1, g5) UP_ADD(3, wd2, g7) UP_ADD(3, wd3, g8)
  const float inv0 = 1.0 / total0, inv1 = 1.0 / total1, inv2 = 1.0 / total2, inv3 = 1.0 / total3;

  Wta wta0, wta1, wta2, wta3;
  Peaks peaks0, peaks1, peaks2, peaks3;
  RawCurve raw0, raw1, raw2, raw3;
  // The raw curves are followed only where the raw agreement is on (a uniform branch).
  const bool raw_agreement_on = kWinnerTakesAll && push.inv_raw_agreement > 0.0;
// One child's filtered texel: stored in place, or into its winner.
#define UP_STORE(chunk, child, filtered, raw_costs)                                   \
  if (inside##child) {                                                                \
    if (!kWinnerTakesAll) {                                                           \
      fine[chunk].v[volume_index(slot, t, fine_plane, fine##child)] = VOLUME_T(filtered); \
    } else if (raw_agreement_on) {                                                    \
      winner_raw_texel(wta##child, peaks##child, raw##child, i, push.num_candidates,  \
                       filtered, raw_costs);                                          \
    } else {                                                                          \
      winner_texel(wta##child, peaks##child, i, push.num_candidates, filtered);       \
    }                                                                                 \
  }
// Every channel of chunk c (a literal: texel arrays take constant indices, volume.glsl).
#define UP_CHUNK(c)                                                                           \
  if (uint(c) < kChunks) {                                                                    \
    for (uint t = 0u; t < kTexels; ++t) {                                                     \
      const uint i = uint(c) * kChannels + t * kPack;  /* the texel's first candidate */      \
      const int cb = int(volume_index(slot, t, coarse_plane, 0u));                            \
      const int fb = int(volume_index(slot, t, fine_plane, 0u));                              \
      const VOLUME_V n0 = VOLUME_FETCH(coarse[c], cb + i0), n1 = VOLUME_FETCH(coarse[c], cb + i1), \
                     n2 = VOLUME_FETCH(coarse[c], cb + i2), n3 = VOLUME_FETCH(coarse[c], cb + i3), \
                     n4 = VOLUME_FETCH(coarse[c], cb + i4), n5 = VOLUME_FETCH(coarse[c], cb + i5), \
                     n6 = VOLUME_FETCH(coarse[c], cb + i6), n7 = VOLUME_FETCH(coarse[c], cb + i7), \
                     n8 = VOLUME_FETCH(coarse[c], cb + i8);                                   \
      const VOLUME_V r0 = VOLUME_FETCH(fine_texels[c], fb + int(fine0)); /* raw */ \
      VOLUME_V s0 = up0 * r0;                                                               \
      s0 += wa0 * n0; s0 += wa1 * n1; s0 += wa2 * n2; s0 += wa3 * n3; s0 += wa4 * n4;             \
      s0 += wa5 * n5; s0 += wa6 * n6; s0 += wa7 * n7; s0 += wa8 * n8;                            \
      const VOLUME_V r1 = VOLUME_FETCH(fine_texels[c], fb + int(fine1)); /* raw */ \
      VOLUME_V s1 = up1 * r1;                                                               \
      s1 += wb0 * n4; s1 += wb1 * n5; s1 += wb2 * n1; s1 += wb3 * n2; s1 += wb4 * n7; s1 += wb5 * n8; \
      const VOLUME_V r2 = VOLUME_FETCH(fine_texels[c], fb + int(fine2)); /* raw */ \
      VOLUME_V s2 = up2 * r2;                                                               \
      s2 += wc0 * n4; s2 += wc1 * n7; s2 += wc2 * n3; s2 += wc3 * n6; s2 += wc4 * n5; s2 += wc5 * n8; \
      const VOLUME_V r3 = VOLUME_FETCH(fine_texels[c], fb + int(fine3)); /* raw */ \
      VOLUME_V s3 = up3 * r3;                                                               \
      s3 += wd0 * n4; s3 += wd1 * n5; s3 += wd2 * n7; s3 += wd3 * n8;                            \
      UP_STORE(c, 0, s0 * inv0, r0) UP_STORE(c, 1, s1 * inv1, r1)                              \
      UP_STORE(c, 2, s2 * inv2, r2) UP_STORE(c, 3, s3 * inv3, r3)                              \
    }                                                                                         \
  }
  FOR_EACH_CHUNK(UP_CHUNK)

// One child's result: its winner's distance, or its smoothed guide (not needed after the last
// pass, which is the one with the winner).
#define UP_FINISH(child)                                                                  \
  if (inside##child) {                                                                    \
    if (kWinnerTakesAll) {                                                                \
      const uint at = (push.distance_first + slot) * fine_plane + fine##child;           \
      distance_map[at] = wta_distance(wta##child, push.num_candidates, push.inv_d_min,   \
                                       push.inv_d_max, push.d_max);                       \
      confidence_map[at] =                                                                \
          peaks_confidence(peaks##child, wta##child, push.num_candidates) *               \
          (raw_agreement_on                                                               \
               ? raw_agreement(raw##child, wta##child.best, push.inv_raw_agreement)       \
               : 1.0);                                                                    \
    } else {                                                                              \
      fine_guide[guide_base + fine##child] =                                              \
          round_guide(guide_sum##child * inv##child) |                                    \
          (kConfidentSigma ? own##child & 0xff000000u : 0u);                              \
    }                                                                                     \
  }
  UP_FINISH(0) UP_FINISH(1) UP_FINISH(2) UP_FINISH(3)
}
