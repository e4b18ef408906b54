#version 450
#extension GL_GOOGLE_include_directive : require
// Adaptive spherical matching, camera selection (ALGORITHM.md §3 step 2), once per calibration:
// for each usable reference pixel with a valid ray, the other camera in which the segment from
// ray * d_min to ray * d_max projects longest (both ends valid and on usable mask pixels,
// longer than 1 pixel). -1 where there is none. Plane slots + slot gets the camera with the next
// longest segment, where it is at least second_power times the longest (-1 where none is), for
// DepthOptions::match_cameras = 2.
layout(local_size_x_id = 100, local_size_y_id = 101, local_size_z_id = 102) in;

#include "camera.glsl"
#include "pixels.glsl"

// Per reference slot: num_cameras records, the reference's frame to each camera's.
CAMERA_RECORDS(0)
layout(std430, set = 0, binding = 1) readonly buffer Masks { uint masks[]; };  // bytes, camera-major
layout(std430, set = 0, binding = 2) writeonly buffer Selection { int selection[]; };  // per slot
layout(push_constant) uniform Push {
  uint width;
  uint height;
  uint num_cameras;
  uint reference;
  uint slot;  // where this reference's cameras and selection map are
  float d_min;
  float d_max;
  uint slots;
  float second_power;
} push;

bool usable(uint camera, vec2 uv) {
  const vec2 px = floor(uv + 0.5);  // nearest pixel
  if (px.x < 0.0 || px.y < 0.0 || px.x >= float(push.width) || px.y >= float(push.height)) return false;
  const uint index = (camera * push.height + uint(px.y)) * push.width + uint(px.x);
  return BYTE_AT(masks, index) != 0u;
}

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (p.x >= push.width || p.y >= push.height) return;
  int best = -1, second = -1;
  float best_displacement = 1.0;  // must exceed one pixel
  float second_displacement = 1.0;
  vec3 ray;
  const uint records = push.slot * push.num_cameras;
  if (usable(push.reference, vec2(p)) &&
      unproject_source(cameras[records + push.reference], vec2(p), ray)) {
    for (uint c = 0u; c < push.num_cameras; ++c) {
      if (c == push.reference) continue;
      const Camera cam = cameras[records + c];
      vec2 near_uv, far_uv;
      if (!project_source(cam, to_camera(cam, ray * push.d_min), near_uv)) continue;
      if (!project_source(cam, to_camera(cam, ray * push.d_max), far_uv)) continue;
      if (!usable(c, near_uv) || !usable(c, far_uv)) continue;
      const float displacement = distance(near_uv, far_uv);
      if (displacement > best_displacement) {
        second_displacement = best_displacement;
        second = best;
        best_displacement = displacement;
        best = int(c);
      } else if (displacement > second_displacement) {
        second_displacement = displacement;
        second = int(c);
      }
    }
  }
  if (second_displacement < push.second_power * best_displacement) second = -1;
  selection[(push.slot * push.height + p.y) * push.width + p.x] = best;
  selection[((push.slots + push.slot) * push.height + p.y) * push.width + p.x] = second;
}
