#version 450
// One pass of a box filter of 2 radius + 1 taps along x (axis 0) or y (axis 1) over `layers`
// single-channel float images stored one after the other. Outside the image: wrap around
// (wrap = 1, for panoramas along x) or read `border`. Two passes make the square box of
// ALGORITHM.md §5 step 3 (31 x 31 for masks and blending weights).
layout(local_size_x_id = 100, local_size_y_id = 101, local_size_z_id = 102) in;

layout(std430, set = 0, binding = 0) readonly buffer Source { float source[]; };
layout(std430, set = 0, binding = 1) writeonly buffer Destination { float destination[]; };
layout(push_constant) uniform Push {
  uint width;
  uint height;
  uint layers;
  int radius;
  uint axis;
  uint wrap;
  float border;
} push;

void main() {
  const uvec3 p = gl_GlobalInvocationID;
  if (p.x >= push.width || p.y >= push.height || p.z >= push.layers) return;
  const uint base = p.z * push.width * push.height;
  const int n = int(push.axis == 0u ? push.width : push.height);
  const int at = int(push.axis == 0u ? p.x : p.y);
  float sum = 0.0;
  for (int k = -push.radius; k <= push.radius; ++k) {
    int i = at + k;
    if (i < 0 || i >= n) {
      if (push.wrap == 0u) {
        sum += push.border;
        continue;
      }
      i = (i % n + n) % n;
    }
    sum += push.axis == 0u ? source[base + p.y * push.width + uint(i)] : source[base + uint(i) * push.width + p.x];
  }
  destination[base + p.y * push.width + p.x] = sum / float(2 * push.radius + 1);
}
