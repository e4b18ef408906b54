#version 450
#extension GL_GOOGLE_include_directive : require
// One pass of directional inpainting (ALGORITHM.md §5 step 2): a hole takes the weighted mean
// of its two background-side neighbours that already hold a value in the previous pass (read
// from `source`, written to `destination`: ping-pong, so the result does not depend on thread
// order). Panoramas wrap around horizontally.
layout(local_size_x_id = 100, local_size_y_id = 101, local_size_z_id = 102) in;

#include "inpaint.glsl"

layout(std430, set = 0, binding = 0) readonly buffer Directions { Direction directions[]; };
layout(std430, set = 0, binding = 1) readonly buffer Source { uint source[]; };
layout(std430, set = 0, binding = 2) writeonly buffer Destination { uint destination[]; };
// filled[pass] becomes 1 when this pass filled any pixel; a pass that fills none has reached the
// fixed point, so the caller may stop (Reprojector does; the stitcher runs a fixed count).
layout(std430, set = 0, binding = 3) buffer Filled { uint filled[]; };
layout(push_constant) uniform Push {
  uint width;
  uint height;
  uint wrap_x;
  uint pass;
} push;

const uint kEmpty = 0xffffffffu;

void main() {
  const uvec2 q = gl_GlobalInvocationID.xy;
  if (q.x >= push.width || q.y >= push.height) return;
  const uint index = q.y * push.width + q.x;
  const uint own = source[index];
  if (own != kEmpty) {
    destination[index] = own;
    return;
  }
  const Direction d = directions[index];
  float sum = 0.0, total = 0.0;
  for (uint k = 0u; k < 2u; ++k) {
    const int n = inpaint_neighbour(d, k, q, push.width, push.height, push.wrap_x);
    if (n < 0) continue;
    const uint value = source[n];
    if (value == kEmpty) continue;
    const float w = k == 0u ? d.weight0 : d.weight1;
    sum += w * uintBitsToFloat(value);
    total += w;
  }
  if (total > 0.0) {
    destination[index] = floatBitsToUint(sum / total);
    filled[push.pass] = 1u;
  } else {
    destination[index] = kEmpty;
  }
}
