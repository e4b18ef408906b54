#version 450
#extension GL_GOOGLE_include_directive : require
// Directional inpainting of colour (ALGORITHM.md §5 step 2, as directional_inpaint.comp does for
// distance), up to 8 passes per dispatch (inpaint_tile.glsl): an empty pixel (alpha 0) takes the
// weighted mean of its two background-side neighbours that held a colour after the previous
// pass. Fills the disocclusions of reprojected views from the background.
layout(local_size_x_id = 100, local_size_y_id = 101, local_size_z_id = 102) in;

#include "inpaint.glsl"
#include "pixels.glsl"

layout(set = 0, binding = 0) uniform usamplerBuffer directions;  // Direction records (inpaint.glsl)
layout(set = 0, binding = 1) uniform usamplerBuffer source;
layout(std430, set = 0, binding = 2) writeonly buffer Destination { uint destination[]; };
// filled[pass] becomes 1 when that pass filled any pixel (see directional_inpaint.comp).
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

const uint kEmptyValue = 0u;

bool is_empty(uint value) { return (value >> 24) == 0u; }

uint blend(uint v0, float w0, uint v1, float w1) {
  vec3 sum = vec3(0.0);
  float total = 0.0;
  if (w0 > 0.0) {
    sum += w0 * unpack_rgb(v0);
    total += w0;
  }
  if (w1 > 0.0) {
    sum += w1 * unpack_rgb(v1);
    total += w1;
  }
  return pack_rgb(uvec3(clamp(sum / total + 0.5, 0.0, 255.0))) | 0xff000000u;
}

#include "inpaint_tile.glsl"

void main() { inpaint_tile(); }
