#version 450
// Divides each reference's weight by the sum over the references at every panorama pixel
// (ALGORITHM.md §5 step 3, before and after the 31 x 31 smoothing).
layout(local_size_x_id = 100, local_size_y_id = 101, local_size_z_id = 102) in;

layout(std430, set = 0, binding = 0) buffer Weights { float weights[]; };
layout(push_constant) uniform Push {
  uint width;
  uint height;
  uint references;
} push;

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (p.x >= push.width || p.y >= push.height) return;
  const uint pixel = p.y * push.width + p.x, plane = push.width * push.height;
  float total = 0.0;
  for (uint k = 0u; k < push.references; ++k) total += weights[k * plane + pixel];
  for (uint k = 0u; k < push.references; ++k) weights[k * plane + pixel] /= total;
}
