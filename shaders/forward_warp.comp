#version 450
#extension GL_GOOGLE_include_directive : require
// Forward warp with a z-buffer (ALGORITHM.md §5 step 1, for any source and target camera):
// every source pixel p with distance D(p) > 0 gives the point D(p) ray(p); in the target's frame
// it projects to the nearest target pixel q (outside: dropped), which keeps the smallest
// distance from the target's centre. atomicMin on the float's bits is exact because positive
// floats order like unsigned integers; empty pixels keep 0xffffffff.
layout(local_size_x_id = 100, local_size_y_id = 101, local_size_z_id = 102) in;

#include "camera.glsl"

layout(std430, set = 0, binding = 0) readonly buffer Cameras { Camera cameras[]; };  // source, target
layout(std430, set = 0, binding = 1) readonly buffer Distance { float distance_map[]; };
layout(std430, set = 0, binding = 2) buffer ZBuffer { uint zbuffer[]; };

void main() {
  const Camera source = cameras[0], target = cameras[1];
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (p.x >= source.width || p.y >= source.height) return;
  const float d = distance_map[p.y * source.width + p.x];
  vec3 ray;
  if (!(d > 0.0) || isinf(d) || !unproject(source, vec2(p), ray)) return;
  const vec3 x = to_camera(target, d * ray);
  vec2 uv;
  if (!project(target, x, uv)) return;
  const vec2 q = floor(uv + 0.5);
  if (q.x < 0.0 || q.y < 0.0 || q.x >= float(target.width) || q.y >= float(target.height)) return;
  atomicMin(zbuffer[uint(q.y) * target.width + uint(q.x)], floatBitsToUint(length(x)));
}
