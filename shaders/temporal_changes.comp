#version 450
#extension GL_GOOGLE_include_directive : require
// Temporal filter, first step (server/stitch/temporal_filter.h): counts the panorama pixels whose
// colour moved since the previous frame by more than `threshold` (the sum over R, G and B of the
// absolute difference, 8-bit levels) into `changed`, once per workgroup. Many changed pixels mean
// the rig or the light moved, and the filter starts again everywhere.
layout(local_size_x_id = 100, local_size_y_id = 101, local_size_z_id = 102) in;

#include "pixels.glsl"

layout(std430, set = 0, binding = 0) readonly buffer Colour { uint colour[]; };
layout(std430, set = 0, binding = 1) readonly buffer Previous { uint previous_colour[]; };
layout(std430, set = 0, binding = 2) buffer Changed { uint changed; };
layout(push_constant) uniform Push {
  uint width;
  uint height;
  float threshold;
} push;

shared uint group_changed;

void main() {
  if (gl_LocalInvocationIndex == 0u) group_changed = 0u;
  barrier();
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (p.x < push.width && p.y < push.height) {
    const uint i = p.y * push.width + p.x;
    const vec3 d = abs(unpack_rgb(colour[i]) - unpack_rgb(previous_colour[i]));
    if (d.x + d.y + d.z > push.threshold) atomicAdd(group_changed, 1u);
  }
  barrier();
  if (gl_LocalInvocationIndex == 0u && group_changed > 0u) atomicAdd(changed, group_changed);
}
