#version 450
#extension GL_GOOGLE_include_directive : require
#ifdef VOLUME_F16
#extension GL_EXT_shader_16bit_storage : require
#endif
// Winner takes all with the parabola sub-candidate step (ALGORITHM.md §3 step 5) over a cost
// volume (wta.glsl); the depth estimator fuses the same steps into the filter's last pass
// instead, and uses this kernel for unfiltered volumes.
layout(local_size_x_id = 100, local_size_y_id = 101, local_size_z_id = 102) in;

#include "volume.glsl"
#include "wta.glsl"

layout(std430, set = 0, binding = 0) readonly buffer Volume { VOLUME_T v[]; } volume[kMaxChunks];
layout(std430, set = 0, binding = 1) writeonly buffer Distance { float distance_map[]; };
layout(push_constant) uniform Push {
  uint width;
  uint height;
  uint num_candidates;
  float inv_d_min;
  float inv_d_max;
  float d_max;
} push;

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (p.x >= push.width || p.y >= push.height) return;
  const uint pixel = p.y * push.width + p.x;
  // One pass in candidate order (uniform indices into the chunk array).
  const uint plane = push.width * push.height;
  Wta wta = wta_start(float(volume[0].v[pixel]));
  for (uint i = 1u; i < push.num_candidates; ++i)
    wta_step(wta, i, float(volume[i / kChannels].v[(i % kChannels) * plane + pixel]));
  distance_map[pixel] =
      wta_distance(wta, push.num_candidates, push.inv_d_min, push.inv_d_max, push.d_max);
}
