#version 450
#extension GL_GOOGLE_include_directive : require
// The filter's guide (ALGORITHM.md §3 step 4): a camera image in BT.709 studio-range YCbCr,
// computed from true R, G, B, clamped to [16, 235] / [16, 240] and rounded to 8 bits. Every
// reference in one dispatch: z is the reference slot, whose guide is plane z of `guide`.
layout(local_size_x_id = 100, local_size_y_id = 101, local_size_z_id = 102) in;

#include "pixels.glsl"

layout(set = 0, binding = 0) uniform usamplerBuffer images;  // RGBA8 texels, camera-major
layout(std430, set = 0, binding = 1) writeonly buffer Guide { uint guide[]; };
layout(push_constant) uniform Push {
  uint width;
  uint height;
  uint references[8];  // the camera of each slot
} push;

void main() {
  const uvec3 g = gl_GlobalInvocationID;
  if (g.x >= push.width || g.y >= push.height) return;
  const uint plane = push.width * push.height, pixel = g.y * push.width + g.x;
  const vec3 rgb = unpack_rgb(texelFetch(images, int(push.references[g.z] * plane + pixel)).x);
  const float y = 16.0 + dot(vec3(0.1826, 0.6142, 0.0620), rgb);
  const float cb = 128.0 + dot(vec3(-0.1006, -0.3386, 0.4392), rgb);
  const float cr = 128.0 + dot(vec3(0.4392, -0.3989, -0.0403), rgb);
  const vec3 ycc = clamp(vec3(y, cb, cr), vec3(16.0), vec3(235.0, 240.0, 240.0));
  guide[g.z * plane + pixel] = pack_rgb(uvec3(floor(ycc + 0.5)));
}
