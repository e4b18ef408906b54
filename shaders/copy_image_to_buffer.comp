#version 450
// Copies an RGBA8 storage image into a buffer of packed texels (r in the lowest byte), scaling
// every channel by `gain` on the way: reads images in kernels that take buffers.
layout(local_size_x_id = 100, local_size_y_id = 101, local_size_z_id = 102) in;

layout(set = 0, binding = 0, std430) writeonly buffer Packed { uint packed[]; };
layout(set = 0, binding = 1, rgba8) readonly uniform image2D source;
layout(push_constant) uniform Push {
  uint width;
  uint height;
  float gain;
} push;

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (p.x >= push.width || p.y >= push.height) return;
  const uvec4 v = uvec4(clamp(floor(imageLoad(source, ivec2(p)) * 255.0 * push.gain + 0.5), 0.0, 255.0));
  packed[p.y * push.width + p.x] = v.r | (v.g << 8) | (v.b << 16) | (v.a << 24);
}
