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
// weights. Each invocation reads and writes only its own fine pixel, so in place is safe.
// With kWinnerTakesAll (the last pass of a cost volume's filter) the filtered costs are not
// stored: each pixel's winner (wta.glsl) is written to `distance_map` instead, which saves the
// winner-takes-all kernel a full read of the volume and this pass its write.
layout(local_size_x_id = 100, local_size_y_id = 101, local_size_z_id = 102) in;

#include "pixels.glsl"
#include "isb_weights.glsl"
#include "volume.glsl"
#include "wta.glsl"

layout(constant_id = 2) const bool kWinnerTakesAll = false;

layout(std430, set = 0, binding = 0) buffer FineGuide { uint fine_guide[]; };
layout(std430, set = 0, binding = 1) readonly buffer CoarseGuide { uint coarse_guide[]; };
layout(std430, set = 0, binding = 2) buffer Fine { VOLUME_T v[]; } fine[kMaxChunks];
layout(std430, set = 0, binding = 3) readonly buffer Coarse { VOLUME_T v[]; } coarse[kMaxChunks];
layout(std430, set = 0, binding = 4) writeonly buffer Distance { float distance_map[]; };
layout(push_constant) uniform Push {
  uint fine_width;
  uint fine_height;
  uint coarse_width;
  uint coarse_height;
  float inv_two_sigma_sq;
  float w_down;
  // kWinnerTakesAll only:
  uint num_candidates;
  float inv_d_min;
  float inv_d_max;
  float d_max;
} push;

void main() {
  const uvec2 f = gl_GlobalInvocationID.xy;
  if (f.x >= push.fine_width || f.y >= push.fine_height) return;
  const ivec2 c = ivec2(f >> 1);
  const uvec2 child = f & 1u;
  // Neighbour offsets (relative to the coarse pixel) and spatial weights per child.
  ivec2 offsets[9];
  float spatial[9];
  int count = 0;
  if (child.x == 0u && child.y == 0u) {  // (2x, 2y): the 3x3 block, 8 at the centre
    for (int j = 0; j < 9; ++j) {
      offsets[j] = ivec2(j % 3 - 1, j / 3 - 1);
      spatial[j] = j == 4 ? 8.0 : 1.0;
    }
    count = 9;
  } else if (child.x == 0u) {  // (2x, 2y + 1)
    offsets[0] = ivec2(0, 0); offsets[1] = ivec2(0, 1);
    offsets[2] = ivec2(-1, 0); offsets[3] = ivec2(-1, 1); offsets[4] = ivec2(1, 0); offsets[5] = ivec2(1, 1);
    spatial[0] = 8.0; spatial[1] = 8.0;
    spatial[2] = 1.0; spatial[3] = 1.0; spatial[4] = 1.0; spatial[5] = 1.0;
    count = 6;
  } else if (child.y == 0u) {  // (2x + 1, 2y)
    offsets[0] = ivec2(0, 0); offsets[1] = ivec2(1, 0);
    offsets[2] = ivec2(0, -1); offsets[3] = ivec2(1, -1); offsets[4] = ivec2(0, 1); offsets[5] = ivec2(1, 1);
    spatial[0] = 8.0; spatial[1] = 8.0;
    spatial[2] = 1.0; spatial[3] = 1.0; spatial[4] = 1.0; spatial[5] = 1.0;
    count = 6;
  } else {  // (2x + 1, 2y + 1)
    offsets[0] = ivec2(0, 0); offsets[1] = ivec2(1, 0); offsets[2] = ivec2(0, 1); offsets[3] = ivec2(1, 1);
    spatial[0] = 1.0; spatial[1] = 1.0; spatial[2] = 1.0; spatial[3] = 1.0;
    count = 4;
  }
  const uint fine_index = f.y * push.fine_width + f.x;
  const uint own_guide = fine_guide[fine_index];
  const ivec2 last = ivec2(push.coarse_width, push.coarse_height) - 1;
  const float w_up = 1.0 - push.w_down;
  uint index[9];
  float weight[9];
  float total = w_up;
  vec3 guide_sum = w_up * unpack_rgb(own_guide);
  for (int j = 0; j < count; ++j) {
    const ivec2 q = clamp(c + offsets[j], ivec2(0), last);
    index[j] = uint(q.y) * push.coarse_width + uint(q.x);
    const uint g = coarse_guide[index[j]];
    weight[j] = push.w_down * spatial[j] * range_weight(own_guide, g, push.inv_two_sigma_sq);
    total += weight[j];
    guide_sum += weight[j] * unpack_rgb(g);
  }
  const float inv_total = 1.0 / total;
  const uint fine_plane = push.fine_width * push.fine_height;
  const uint coarse_plane = push.coarse_width * push.coarse_height;
  Wta wta;
  for (uint chunk = 0u; chunk < kChunks; ++chunk) {
    for (uint k = 0u; k < kChannels; ++k) {
      float sum = w_up * float(fine[chunk].v[k * fine_plane + fine_index]);
      for (int j = 0; j < count; ++j)
        sum += weight[j] * float(coarse[chunk].v[k * coarse_plane + index[j]]);
      const float filtered = sum * inv_total;
      if (!kWinnerTakesAll) {
        fine[chunk].v[k * fine_plane + fine_index] = VOLUME_T(filtered);
        continue;
      }
      const uint i = chunk * kChannels + k;
      if (i == 0u) {
        wta = wta_start(filtered);
      } else if (i < push.num_candidates) {
        wta_step(wta, i, filtered);
      }
    }
  }
  if (kWinnerTakesAll) {
    distance_map[fine_index] =
        wta_distance(wta, push.num_candidates, push.inv_d_min, push.inv_d_max, push.d_max);
    return;  // the guide is not needed after the last pass
  }
  fine_guide[fine_index] = round_guide(guide_sum * inv_total);
}
