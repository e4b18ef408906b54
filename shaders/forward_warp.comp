#version 450
#extension GL_GOOGLE_include_directive : require
// Forward warp with a z-buffer (ALGORITHM.md §5 step 1, for any source and target camera):
// every source pixel p with distance D(p) > 0 gives the point D(p) ray(p); in the target's frame
// it projects to the nearest target pixel q (outside: dropped), which keeps the smallest
// distance from the target's centre. atomicMin on the float's bits is exact because positive
// floats order like unsigned integers; empty pixels keep 0xffffffff.
//
// With max_splat > 1 (novel views that magnify the source), a source pixel instead covers the
// target pixels whose centres fall inside its footprint: the bounding box of the parallelogram
// spanned by where its right and lower neighbours at the same distance land (so footprints of
// neighbouring pixels leave no cracks), at most max_splat pixels wide. The nearest pixel
// is always covered, so max_splat <= 1 is exactly the paper's warp.
//
// z is the layer (forward_warp.h): cameras 2z and 2z + 1, and plane z of the distance maps and
// of the z-buffer.
layout(local_size_x_id = 100, local_size_y_id = 101, local_size_z_id = 102) in;

#include "camera.glsl"

CAMERA_RECORDS(0)  // source, target per layer
layout(set = 0, binding = 1) uniform samplerBuffer distance_map;  // per layer (a texel buffer)
layout(std430, set = 0, binding = 2) buffer ZBuffer { uint zbuffer[]; };
layout(push_constant) uniform Push {
  float max_splat;
} push;

void write_min(Camera target, uint layer, ivec2 q, uint bits) {
  if (model_of(target, kTargetModel) == kModelEquirectangular) q.x = (q.x % int(target.width) + int(target.width)) % int(target.width);
  if (q.x < 0 || q.y < 0 || q.x >= int(target.width) || q.y >= int(target.height)) return;
  atomicMin(zbuffer[(layer * target.height + uint(q.y)) * target.width + uint(q.x)], bits);
}

void main() {
  const uint layer = gl_GlobalInvocationID.z;
  const Camera source = cameras[2u * layer], target = cameras[2u * layer + 1u];
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (p.x >= source.width || p.y >= source.height) return;
  const float d = texelFetch(distance_map, int((layer * source.height + p.y) * source.width + p.x)).x;
  vec3 ray;
  if (!(d > 0.0) || isinf(d) || !unproject_source(source, vec2(p), ray)) return;
  const vec3 x = to_camera(target, d * ray);
  vec2 uv;
  if (!project_target(target, x, uv)) return;
  const uint bits = floatBitsToUint(length(x));
  const ivec2 nearest = ivec2(floor(uv + 0.5));
  if (push.max_splat <= 1.0) {
    write_min(target, layer, nearest, bits);
    return;
  }
  vec2 half_extent = vec2(0.0);
  for (int k = 0; k < 2; ++k) {
    vec3 neighbour_ray;
    vec2 neighbour_uv;
    if (!unproject_source(source, vec2(p) + (k == 0 ? vec2(1.0, 0.0) : vec2(0.0, 1.0)), neighbour_ray) ||
        !project_target(target, to_camera(target, d * neighbour_ray), neighbour_uv)) {
      continue;
    }
    vec2 delta = neighbour_uv - uv;
    if (model_of(target, kTargetModel) == kModelEquirectangular) delta.x -= float(target.width) * round(delta.x / float(target.width));
    half_extent += 0.5 * abs(delta);  // the footprint's bounding box: +-(dx + dy) / 2
  }
  half_extent = min(half_extent, vec2(0.5 * push.max_splat));
  const ivec2 lo = min(ivec2(ceil(uv - half_extent)), nearest);
  const ivec2 hi = max(ivec2(floor(uv + half_extent)), nearest);
  for (int y = lo.y; y <= hi.y; ++y) {
    for (int x_ = lo.x; x_ <= hi.x; ++x_) write_min(target, layer, ivec2(x_, y), bits);
  }
}
