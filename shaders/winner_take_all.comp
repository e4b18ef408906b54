#version 450
#extension GL_GOOGLE_include_directive : require
// Winner takes all with the parabola sub-candidate step (ALGORITHM.md §3 step 5): the first
// minimal candidate i*, delta = (C(i*-1) - C(i*+1)) / (2 (C(i*-1) + C(i*+1) - 2 C(i*) + 1e-8))
// clamped to [-0.5, 0.5] (0 at the first or last candidate), mapped through the
// inverse-distance spacing to a distance. A flat cost (max = min) gives d_max.
layout(local_size_x_id = 100, local_size_y_id = 101, local_size_z_id = 102) in;

#include "volume.glsl"

layout(std430, set = 0, binding = 0) readonly buffer Volume { float v[]; } volume[kMaxChunks];
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
  // One pass in candidate order (uniform indices into the chunk array), remembering the
  // neighbours of the current minimum.
  const uint plane = push.width * push.height;
  float lowest = volume[0].v[pixel];
  float highest = lowest;
  float before = 0.0, after = 0.0, previous = lowest;
  uint best = 0u;
  bool want_after = true;
  for (uint i = 1u; i < push.num_candidates; ++i) {
    const float c = volume[i / kChannels].v[(i % kChannels) * plane + pixel];
    if (want_after) {
      after = c;
      want_after = false;
    }
    if (c < lowest) {
      lowest = c;
      best = i;
      before = previous;
      want_after = true;
    }
    highest = max(highest, c);
    previous = c;
  }
  if (highest == lowest) {
    distance_map[pixel] = push.d_max;
    return;
  }
  float delta = 0.0;
  if (best > 0u && best + 1u < push.num_candidates) {
    delta = clamp(0.5 * (before - after) / (before + after - 2.0 * lowest + 1e-8), -0.5, 0.5);
  }
  const float k = float(best) + delta;
  const float inverse = push.inv_d_min + (push.inv_d_max - push.inv_d_min) * k / float(push.num_candidates - 1u);
  distance_map[pixel] = 1.0 / inverse;
}
