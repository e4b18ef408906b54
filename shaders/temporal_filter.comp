#version 450
#extension GL_GOOGLE_include_directive : require
// Temporal filter, second step (server/stitch/temporal_filter.h; temporal_filter_cpu is the
// reference): per panorama pixel, a running mean of inverse distance over the frames since the
// pixel last changed, at most `max_frames` of them (x += (z - x) / n), so a static scene stops
// flickering. It starts again (x = z, n = 1) on the first frame, where `changed` (temporal_changes)
// exceeds `reset_pixels` (the rig or the light moved), where the pixel's colour moved by more
// than `threshold`, and where either has no value. A new inverse distance `jump` or more from
// the mean (something moved in depth) starts it again where the frame's confidence is at least
// `confident`; below, the jump is kept in `pending_inverse` and joins the mean, and the pixel
// starts again when the next frame jumps to within `jump` of it. The filtered distance replaces
// `distance`.
layout(local_size_x_id = 100, local_size_y_id = 101, local_size_z_id = 102) in;

#include "pixels.glsl"

layout(std430, set = 0, binding = 0) buffer Distance { float distance[]; };
layout(std430, set = 0, binding = 1) readonly buffer Colour { uint colour[]; };
layout(std430, set = 0, binding = 2) buffer Mean { float mean_inverse[]; };
layout(std430, set = 0, binding = 3) buffer Count { float count[]; };
layout(std430, set = 0, binding = 4) buffer Previous { uint previous_colour[]; };
layout(std430, set = 0, binding = 5) readonly buffer Changed { uint changed; };
layout(std430, set = 0, binding = 6) readonly buffer Confidence { float confidence[]; };
layout(std430, set = 0, binding = 7) buffer Pending { float pending_inverse[]; };
layout(push_constant) uniform Push {
  uint width;
  uint height;
  float threshold;
  float jump;
  float max_frames;
  uint reset_pixels;
  uint first;
  float confident;
} push;

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (p.x >= push.width || p.y >= push.height) return;
  const uint i = p.y * push.width + p.x;
  const float d = distance[i];
  const float z = d > 0.0 ? 1.0 / d : 0.0;
  const vec3 moved = abs(unpack_rgb(colour[i]) - unpack_rgb(previous_colour[i]));
  float x = mean_inverse[i], n = count[i];
  bool restart = push.first != 0u || changed > push.reset_pixels ||
                 moved.x + moved.y + moved.z > push.threshold || !(z > 0.0) || !(x > 0.0);
  float pending = 0.0;
  if (!restart && abs(z - x) >= push.jump) {
    const float earlier = pending_inverse[i];
    if (confidence[i] >= push.confident || (earlier > 0.0 && abs(z - earlier) < push.jump))
      restart = true;
    else
      pending = z;
  }
  if (restart) {
    x = z;
    n = 1.0;
  } else {
    n = min(n + 1.0, push.max_frames);
    x += (z - x) / n;
  }
  pending_inverse[i] = pending;
  mean_inverse[i] = x;
  count[i] = n;
  previous_colour[i] = colour[i];
  distance[i] = x > 0.0 ? 1.0 / x : 0.0;
}
