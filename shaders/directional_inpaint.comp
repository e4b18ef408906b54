#version 450
#extension GL_GOOGLE_include_directive : require
// Directional inpainting of distance (ALGORITHM.md §5 step 2), up to 8 passes per dispatch
// (inpaint_tile.glsl): in each pass a hole takes the weighted mean of its two background-side
// neighbours that held a value after the previous pass (ping-pong, so the result does not depend
// on thread order). Panoramas wrap around horizontally.
layout(local_size_x_id = 100, local_size_y_id = 101, local_size_z_id = 102) in;

#include "inpaint.glsl"

layout(set = 0, binding = 0) uniform usamplerBuffer directions;  // Direction records (inpaint.glsl)
layout(set = 0, binding = 1) uniform usamplerBuffer source;
layout(std430, set = 0, binding = 2) writeonly buffer Destination { uint destination[]; };
// filled[pass] becomes 1 when that pass filled any pixel; a pass that fills none has reached the
// fixed point, so the caller may stop (Reprojector does; the stitcher runs a fixed count).
layout(std430, set = 0, binding = 3) buffer Filled { uint filled[]; };
// Per tile and layer, whether later dispatches may skip it (inpaint_tile.glsl).
layout(std430, set = 0, binding = 4) buffer Status { uint tile_status[]; };
layout(push_constant) uniform Push {
  uint width;
  uint height;
  uint wrap_x;
  uint pass;    // the first pass of this dispatch
  uint passes;  // 1 to 8
  uint status_set;  // which tile_status set this dispatch writes: 0 and 1 in turn (inpaint_tile.glsl)
} push;

const uint kEmptyValue = 0xffffffffu;

bool is_empty(uint value) { return value == kEmptyValue; }

uint blend(uint v0, float w0, uint v1, float w1) {
  float sum = 0.0, total = 0.0;
  if (w0 > 0.0) {
    sum += w0 * uintBitsToFloat(v0);
    total += w0;
  }
  if (w1 > 0.0) {
    sum += w1 * uintBitsToFloat(v1);
    total += w1;
  }
  return floatBitsToUint(sum / total);
}

#include "inpaint_tile.glsl"

void main() { inpaint_tile(); }
