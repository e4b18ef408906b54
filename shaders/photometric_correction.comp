#version 450
// Undoes each camera's photometric response (server/depth/photometric_model.h) in packed RGBA8
// images, in place: every channel divided by the camera's gain and its vignetting
// V = max(0.05, 1 + b1 t + b2 t^2), t = (theta / 110 deg)^2 read from a per-pixel table of 16-bit
// floats, two to a uint (-1 where the pixel has no ray: left as it is), rounded and clamped to
// 255. PhotometricCorrection::apply is the CPU check.
layout(local_size_x_id = 100, local_size_y_id = 101, local_size_z_id = 102) in;

layout(std430, set = 0, binding = 0) buffer Pixels { uint pixels[]; };  // image after image
layout(std430, set = 0, binding = 1) readonly buffer Angles { uint t2[]; };  // same order, halves
// Per image: (1 / gain r, 1 / gain g, 1 / gain b, b1), (b2, 0, 0, 0).
layout(std430, set = 0, binding = 2) readonly buffer Responses { vec4 responses[]; };
layout(push_constant) uniform Push {
  uint width;
  uint height;
  uint images;
} push;

void main() {
  const uvec3 id = gl_GlobalInvocationID;
  if (id.x >= push.width || id.y >= push.height || id.z >= push.images) return;
  const uint i = (id.z * push.height + id.y) * push.width + id.x;
  const vec2 pair = unpackHalf2x16(t2[i >> 1]);
  const float t = (i & 1u) == 0u ? pair.x : pair.y;
  if (t < 0.0) return;
  const vec4 gains = responses[2 * id.z];
  const float b2 = responses[2 * id.z + 1].x;
  const float v = max(0.05, 1.0 + gains.w * t + b2 * t * t);
  const vec4 rgba = unpackUnorm4x8(pixels[i]) * 255.0;
  const vec3 corrected = min(floor(rgba.rgb * gains.rgb / v + 0.5), vec3(255.0));
  pixels[i] = packUnorm4x8(vec4(corrected, rgba.a) / 255.0);
}
