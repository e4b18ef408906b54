#version 450
#extension GL_GOOGLE_include_directive : require
// Colour of a reprojected view: every target pixel with a (warped and inpainted) distance d
// gives the point d ray(q); its colour is sampled bilinearly from the source image where that
// point projects (ALGORITHM.md §5 step 4, with the source as the only reference). A point the
// source cannot see (its distance map holds something nearer there, by more than
// `occlusion_tolerance` relative) was disoccluded: it stays empty (alpha 0) for
// directional_inpaint_color.comp to fill from the background side.
layout(local_size_x_id = 100, local_size_y_id = 101, local_size_z_id = 102) in;

#include "camera.glsl"
#include "pixels.glsl"

CAMERA_RECORDS(0)  // source, target
// Read through texel buffers (gathers on CPU devices, the texture cache on GPUs).
layout(set = 0, binding = 1) uniform usamplerBuffer warped;  // target, float bits
layout(set = 0, binding = 2) uniform samplerBuffer source_distance;
layout(set = 0, binding = 3) uniform usamplerBuffer source_colour;
layout(std430, set = 0, binding = 4) writeonly buffer Colour { uint colour[]; };  // target RGBA8
layout(push_constant) uniform Push {
  float occlusion_tolerance;
} push;

const uint kEmpty = 0xffffffffu;

// Source pixel index of integer coordinates, wrapping panoramas horizontally, clamping others.
uint source_index(Camera source, ivec2 p) {
  if (model_of(source, kSourceModel) == kModelEquirectangular) {
    p.x = (p.x % int(source.width) + int(source.width)) % int(source.width);
  } else {
    p.x = clamp(p.x, 0, int(source.width) - 1);
  }
  p.y = clamp(p.y, 0, int(source.height) - 1);
  return uint(p.y) * source.width + uint(p.x);
}

vec3 colour_at(Camera source, ivec2 p) {
  return unpack_rgb(texelFetch(source_colour, int(source_index(source, p))).x);
}

void main() {
  const Camera source = cameras[0], target = cameras[1];
  const uvec2 q = gl_GlobalInvocationID.xy;
  if (q.x >= target.width || q.y >= target.height) return;
  const uint index = q.y * target.width + q.x;
  const uint bits = texelFetch(warped, int(index)).x;
  vec3 ray;
  if (bits == kEmpty || !unproject_target(target, vec2(q), ray)) {
    colour[index] = 0u;
    return;
  }
  // rows hold target_from_source (R | t): x_source = R^T (x_target - t); mat3(rows) is R^T.
  const mat3 source_from_target = mat3(target.row0.xyz, target.row1.xyz, target.row2.xyz);
  const vec3 x_target = uintBitsToFloat(bits) * ray;
  const vec3 x = source_from_target * (x_target - vec3(target.row0.w, target.row1.w, target.row2.w));
  vec2 uv;
  if (!project_source(source, x, uv)) {
    colour[index] = 0u;
    return;
  }
  const float seen = texelFetch(source_distance, int(source_index(source, ivec2(floor(uv + 0.5))))).x;
  if (seen > 0.0 && seen < length(x) * (1.0 - push.occlusion_tolerance)) {
    colour[index] = 0u;
    return;
  }
  const vec2 base = floor(uv);
  const vec2 f = uv - base;
  const ivec2 b = ivec2(base);
  const vec3 c00 = colour_at(source, b), c10 = colour_at(source, b + ivec2(1, 0));
  const vec3 c01 = colour_at(source, b + ivec2(0, 1)), c11 = colour_at(source, b + ivec2(1, 1));
  const vec3 c = mix(mix(c00, c10, f.x), mix(c01, c11, f.x), f.y);
  colour[index] = pack_rgb(uvec3(clamp(c + 0.5, 0.0, 255.0))) | 0xff000000u;
}
