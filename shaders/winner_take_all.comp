#version 450
#extension GL_GOOGLE_include_directive : require
// Winner takes all with the parabola sub-candidate step (ALGORITHM.md §3 step 5) over a cost
// volume (wta.glsl); the depth estimator fuses the same steps into the filter's last pass
// instead, and uses this kernel for unfiltered volumes. z is the volume's slot; its distance
// map is plane first + z of `distance_map`, its confidence (wta.glsl) the same plane of
// `confidence_map`.
layout(local_size_x_id = 100, local_size_y_id = 101, local_size_z_id = 102) in;

#include "volume.glsl"
#include "wta.glsl"

layout(set = 0, binding = 0) uniform samplerBuffer volume[kMaxChunks];
layout(std430, set = 0, binding = 1) writeonly buffer Distance { float distance_map[]; };
layout(std430, set = 0, binding = 2) writeonly buffer Confidence { float confidence_map[]; };
layout(push_constant) uniform Push {
  uint width;
  uint height;
  uint num_candidates;
  float inv_d_min;
  float inv_d_max;
  float d_max;
  uint first;
} push;

// The candidates of one chunk into `wta`.
void wta_chunk(samplerBuffer chunk_texels, uint chunk, uint slot, uint plane, uint pixel,
               inout Wta wta, inout Peaks peaks) {
  for (uint t = 0u; t < kTexels; ++t) {
    const VOLUME_V c = VOLUME_FETCH(chunk_texels, int(volume_index(slot, t, plane, pixel)));
    winner_texel(wta, peaks, chunk * kChannels + t * kPack, push.num_candidates, c);
  }
}

void main() {
  const uvec3 g = gl_GlobalInvocationID;
  if (g.x >= push.width || g.y >= push.height) return;
  const uint plane = push.width * push.height, pixel = g.y * push.width + g.x;
  // One pass in candidate order, chunk after chunk (candidate 0 starts the winner).
  Wta wta;
  Peaks peaks;
#define WTA_CHUNK(c) \
  if (uint(c) < kChunks) wta_chunk(volume[c], uint(c), g.z, plane, pixel, wta, peaks);
  FOR_EACH_CHUNK(WTA_CHUNK)
  const uint at = (push.first + g.z) * plane + pixel;
  distance_map[at] =
      wta_distance(wta, push.num_candidates, push.inv_d_min, push.inv_d_max, push.d_max);
  confidence_map[at] = peaks_confidence(peaks, wta, push.num_candidates);
}
