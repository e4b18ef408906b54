#version 450
#extension GL_GOOGLE_include_directive : require
// Raw blending weight of each reference at each panorama pixel (ALGORITHM.md §5 step 3): the
// panorama direction in c's axes must project validly, and so must pxNear = project(d_min dir -
// t_c) and pxFar = project(d_max dir - t_c) (as the page writes them); with uv, pxNear and pxFar
// clamped to [0.1, W - 1.1] x [0.1, H - 1.1] and the box-smoothed mask > 0.99 at pxNear and pxFar
// (bilinear), the weight is exp(-|pxFar - pxNear|^2 / (1e-4 W H)), else 1e-8.
layout(local_size_x_id = 100, local_size_y_id = 101, local_size_z_id = 102) in;

#include "camera.glsl"

// Per reference k: cameras[2k] at the matching resolution, rows [cam_from_rig rotation | t_c].
CAMERA_RECORDS(0)
layout(std430, set = 0, binding = 1) readonly buffer Masks { float masks[]; };  // smoothed, per reference
layout(std430, set = 0, binding = 2) writeonly buffer Weights { float weights[]; };  // per reference, panorama
layout(push_constant) uniform Push {
  uint width;
  uint height;
  uint references;
  float d_min;
  float d_max;
} push;

float mask_at(uint k, Camera c, vec2 uv) {
  const vec2 f = floor(uv);
  const vec2 t = uv - f;
  float v[4];
  for (int j = 0; j < 4; ++j) {
    const ivec2 q = clamp(ivec2(f) + ivec2(j & 1, j >> 1), ivec2(0), ivec2(c.width, c.height) - 1);
    v[j] = masks[k * c.width * c.height + uint(q.y) * c.width + uint(q.x)];
  }
  return mix(mix(v[0], v[1], t.x), mix(v[2], v[3], t.x), t.y);
}

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (p.x >= push.width || p.y >= push.height) return;
  const float phi = (float(p.y) + 0.5) * kPi / float(push.height) - 0.5 * kPi;
  const float theta = (float(p.x) + 0.5) * 2.0 * kPi / float(push.width) + kPi;
  const vec3 dir = vec3(cos(phi) * sin(theta), sin(phi), cos(phi) * cos(theta));
  for (uint k = 0u; k < push.references; ++k) {
    const Camera c = cameras[2u * k];
    const vec3 dir_c = vec3(dot(c.row0.xyz, dir), dot(c.row1.xyz, dir), dot(c.row2.xyz, dir));
    const vec3 t_c = vec3(c.row0.w, c.row1.w, c.row2.w);
    vec2 uv, near_px, far_px;
    const bool valid_dir = project_source(c, dir_c, uv);
    const bool valid_near = project_source(c, push.d_min * dir_c - t_c, near_px);
    const bool valid_far = project_source(c, push.d_max * dir_c - t_c, far_px);
    const vec2 lo = vec2(0.1), hi = vec2(c.width, c.height) - 1.1;
    near_px = clamp(near_px, lo, hi);
    far_px = clamp(far_px, lo, hi);
    float weight = 1e-8;
    if (valid_dir && valid_near && valid_far && mask_at(k, c, near_px) > 0.99 && mask_at(k, c, far_px) > 0.99) {
      const vec2 d = far_px - near_px;
      weight = exp(-dot(d, d) / (1e-4 * float(c.width) * float(c.height)));
    }
    weights[k * push.width * push.height + p.y * push.width + p.x] = weight;
  }
}
