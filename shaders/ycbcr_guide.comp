#version 450
#extension GL_GOOGLE_include_directive : require
// The filter's guide (ALGORITHM.md §3 step 4): a camera image in BT.709 studio-range YCbCr,
// computed from true R, G, B, clamped to [16, 235] / [16, 240] and rounded to 8 bits.
layout(local_size_x_id = 100, local_size_y_id = 101, local_size_z_id = 102) in;

#include "pixels.glsl"

layout(std430, set = 0, binding = 0) readonly buffer Images { uint images[]; };
layout(std430, set = 0, binding = 1) writeonly buffer Guide { uint guide[]; };
layout(push_constant) uniform Push {
  uint width;
  uint height;
  uint camera;
} push;

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (p.x >= push.width || p.y >= push.height) return;
  const uint pixel = p.y * push.width + p.x;
  const vec3 rgb = unpack_rgb(images[push.camera * push.width * push.height + pixel]);
  const float y = 16.0 + dot(vec3(0.1826, 0.6142, 0.0620), rgb);
  const float cb = 128.0 + dot(vec3(-0.1006, -0.3386, 0.4392), rgb);
  const float cr = 128.0 + dot(vec3(0.4392, -0.3989, -0.0403), rgb);
  const vec3 ycc = clamp(vec3(y, cb, cr), vec3(16.0), vec3(235.0, 240.0, 240.0));
  guide[pixel] = pack_rgb(uvec3(floor(ycc + 0.5)));
}
