#version 450
#extension GL_GOOGLE_include_directive : require
// Background directions for directional inpainting (ALGORITHM.md §5 step 2), once per pose: for
// target pixel q with ray rho (taken in the source's axes), v = project(d_max rho) -
// project(d_min rho) in the target is where the background lies. Of the 8 neighbours, the two
// whose unit offset has the largest positive dot product with v / |v| are kept, weighted by it.
// z is the layer (forward_warp.h): target camera 2z + 1, plane z of `directions`.
layout(local_size_x_id = 100, local_size_y_id = 101, local_size_z_id = 102) in;

#include "camera.glsl"
#include "inpaint.glsl"

CAMERA_RECORDS(0)  // source, target
layout(std430, set = 0, binding = 1) writeonly buffer Directions { Direction directions[]; };
layout(push_constant) uniform Push {
  float d_min;
  float d_max;
} push;

void main() {
  const uint layer = gl_GlobalInvocationID.z;
  const Camera target = cameras[2u * layer + 1u];
  const uvec2 q = gl_GlobalInvocationID.xy;
  if (q.x >= target.width || q.y >= target.height) return;
  Direction result = Direction(0xffffu, 0.0, 0.0, 0u);
  vec3 ray;
  if (unproject_target(target, vec2(q), ray)) {
    // The target ray's direction expressed in the source's axes (rows hold target_from_source).
    const mat3 target_from_source = transpose(mat3(target.row0.xyz, target.row1.xyz, target.row2.xyz));
    const vec3 rho = transpose(target_from_source) * ray;
    vec2 near_uv, far_uv;
    const bool ok = project_target(target, to_camera(target, push.d_min * rho), near_uv) &&
                    project_target(target, to_camera(target, push.d_max * rho), far_uv);
    vec2 v = far_uv - near_uv;
    if (model_of(target, kTargetModel) == kModelEquirectangular) v.x -= float(target.width) * round(v.x / float(target.width));
    if (ok && length(v) > 1e-6) {
      const vec2 dir = normalize(v);
      float best0 = 0.0, best1 = 0.0;
      uint code0 = 0xffu, code1 = 0xffu;
      for (uint k = 0u; k < 8u; ++k) {
        const float dot_k = dot(normalize(vec2(neighbour_offset(k))), dir);
        if (dot_k > best0) {
          best1 = best0;
          code1 = code0;
          best0 = dot_k;
          code0 = k;
        } else if (dot_k > best1) {
          best1 = dot_k;
          code1 = k;
        }
      }
      result = Direction(code0 | (code1 << 8), best0, best1, 0u);
    }
  }
  directions[(layer * target.height + q.y) * target.width + q.x] = result;
}
