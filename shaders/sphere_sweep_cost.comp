#version 450
#extension GL_GOOGLE_include_directive : require
#ifdef VOLUME_F16
#extension GL_EXT_shader_16bit_storage : require
#endif
// Sphere sweep and matching cost (ALGORITHM.md §3 steps 1 and 3): for each reference pixel and
// candidate distance d_i (uniform in inverse distance), sample the selected camera bilinearly
// at the projection of ray * d_i (taps outside the image read 0) and store the L1 colour
// difference (0-255 per channel, summed) clamped at 500. Pixels without a selected camera get
// cost 0 for every candidate.
layout(local_size_x_id = 100, local_size_y_id = 101, local_size_z_id = 102) in;

#include "camera.glsl"
#include "pixels.glsl"
#include "volume.glsl"

layout(std430, set = 0, binding = 0) readonly buffer Cameras { Camera cameras[]; };
layout(std430, set = 0, binding = 1) readonly buffer Images { uint images[]; };  // RGBA8, camera-major
layout(std430, set = 0, binding = 2) readonly buffer Selection { int selection[]; };
layout(std430, set = 0, binding = 3) writeonly buffer Volume { VOLUME_T v[]; } volume[kMaxChunks];
layout(push_constant) uniform Push {
  uint width;
  uint height;
  uint reference;
  uint num_candidates;
  float inv_d_min;
  float inv_d_max;
} push;

vec3 tap(uint camera, int x, int y) {
  if (x < 0 || y < 0 || x >= int(push.width) || y >= int(push.height)) return vec3(0.0);
  return unpack_rgb(images[(camera * push.height + uint(y)) * push.width + uint(x)]);
}

vec3 bilinear(uint camera, vec2 uv) {
  if (uv.x < -2.0 || uv.y < -2.0 || uv.x > float(push.width) + 1.0 || uv.y > float(push.height) + 1.0) {
    return vec3(0.0);
  }
  const vec2 f = floor(uv);
  const vec2 t = uv - f;
  const int x = int(f.x), y = int(f.y);
  return mix(mix(tap(camera, x, y), tap(camera, x + 1, y), t.x),
             mix(tap(camera, x, y + 1), tap(camera, x + 1, y + 1), t.x), t.y);
}

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (p.x >= push.width || p.y >= push.height) return;
  const uint pixel = p.y * push.width + p.x;
  const int selected = selection[pixel];
  vec3 ray = vec3(0.0);
  const bool matching = selected >= 0 && unproject_source(cameras[push.reference], vec2(p), ray);
  const vec3 reference_rgb = unpack_rgb(images[push.reference * push.width * push.height + pixel]);
  const float step = (push.inv_d_max - push.inv_d_min) / float(push.num_candidates - 1u);
  // What does not change with the candidate, once per pixel: the selected camera and the ray in
  // its axes (the point at distance d is d * rotated + translation).
  const Camera c = cameras[max(selected, 0)];
  const vec3 rotated = vec3(dot(c.row0.xyz, ray), dot(c.row1.xyz, ray), dot(c.row2.xyz, ray));
  const vec3 translation = vec3(c.row0.w, c.row1.w, c.row2.w);
  for (uint i = 0u; i < kChunks * kChannels; ++i) {
    float cost = 0.0;
    if (matching && i < push.num_candidates) {
      const float distance_i = 1.0 / (push.inv_d_min + step * float(i));
      vec2 uv;
      vec3 rgb = vec3(0.0);
      if (project_source(c, distance_i * rotated + translation, uv)) rgb = bilinear(uint(selected), uv);
      const vec3 d = abs(rgb - reference_rgb);
      cost = min(d.x + d.y + d.z, 500.0);
    }
    volume[i / kChannels].v[(i % kChannels) * push.width * push.height + pixel] = VOLUME_T(cost);
  }
}
