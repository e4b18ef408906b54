#version 450
#extension GL_GOOGLE_include_directive : require
#ifdef VOLUME_F16
#extension GL_EXT_shader_16bit_storage : require
#endif
// Inter-scale bilateral filter, down pass (ALGORITHM.md §4): coarse pixel (x, y) gathers the
// 3x3 neighbourhood of fine pixel (2x, 2y) (indices clamped) with spatial weights 1 / 0.5 / 0.25
// (centre / edge / corner), each off-centre weight times exp(-g^2 / (2 sigma_I^2)) + 0.01. The
// coarse guide (rounded to 8 bits) and every channel are the normalised weighted sums.
layout(local_size_x_id = 100, local_size_y_id = 101, local_size_z_id = 102) in;

#include "pixels.glsl"
#include "isb_weights.glsl"
#include "volume.glsl"

layout(std430, set = 0, binding = 0) readonly buffer FineGuide { uint fine_guide[]; };
layout(std430, set = 0, binding = 1) writeonly buffer CoarseGuide { uint coarse_guide[]; };
layout(std430, set = 0, binding = 2) readonly buffer Fine { VOLUME_T v[]; } fine[kMaxChunks];
layout(std430, set = 0, binding = 3) writeonly buffer Coarse { VOLUME_T v[]; } coarse[kMaxChunks];
layout(push_constant) uniform Push {
  uint fine_width;
  uint fine_height;
  uint coarse_width;
  uint coarse_height;
  float inv_two_sigma_sq;
} push;

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (p.x >= push.coarse_width || p.y >= push.coarse_height) return;
  const ivec2 centre = 2 * ivec2(p);
  const ivec2 last = ivec2(push.fine_width, push.fine_height) - 1;
  const uint centre_guide = fine_guide[uint(centre.y) * push.fine_width + uint(centre.x)];
  uint index[9];
  float weight[9];
  float total = 0.0;
  vec3 guide_sum = vec3(0.0);
  for (int j = 0; j < 9; ++j) {
    const ivec2 offset = ivec2(j % 3 - 1, j / 3 - 1);
    const ivec2 q = clamp(centre + offset, ivec2(0), last);
    index[j] = uint(q.y) * push.fine_width + uint(q.x);
    const uint g = fine_guide[index[j]];
    const int manhattan = abs(offset.x) + abs(offset.y);
    weight[j] = manhattan == 0 ? 1.0 : (manhattan == 1 ? 0.5 : 0.25) * range_weight(centre_guide, g, push.inv_two_sigma_sq);
    total += weight[j];
    guide_sum += weight[j] * unpack_rgb(g);
  }
  const uint out_index = p.y * push.coarse_width + p.x;
  coarse_guide[out_index] = round_guide(guide_sum / total);
  const float inv_total = 1.0 / total;
  const uint fine_plane = push.fine_width * push.fine_height;
  const uint coarse_plane = push.coarse_width * push.coarse_height;
  for (uint chunk = 0u; chunk < kChunks; ++chunk) {
    for (uint k = 0u; k < kChannels; ++k) {
      float sum = 0.0;
      for (int j = 0; j < 9; ++j)
        sum += weight[j] * float(fine[chunk].v[k * fine_plane + index[j]]);
      coarse[chunk].v[k * coarse_plane + out_index] = VOLUME_T(sum * inv_total);
    }
  }
}
