#version 450
#extension GL_GOOGLE_include_directive : require
// Merge into the panorama (ALGORITHM.md §5 step 4). For each reference c, the panorama
// direction in c's axes gives uv (clamped to [0.1, W - 1.1] x [0.1, H - 1.1]); r is the warped and
// inpainted distance there (bilinear over the taps that hold a value), accumulated as weight / r.
// Colour: d' = min(r, original distance at uv), P = d' ray(uv) + t_c, and the colour image (at
// its own resolution) is sampled bilinearly at project(P). Output distance = 1 / sum(weight / r)
// over the references that had a value (weights renormalised); 0 where none had.
layout(local_size_x_id = 100, local_size_y_id = 101, local_size_z_id = 102) in;

#include "camera.glsl"
#include "pixels.glsl"

// Per reference k: cameras[2k] is its camera at the matching resolution with rows
// [cam_from_rig rotation | t_c]; cameras[2k + 1] its camera at the colour resolution.
CAMERA_RECORDS(0)
// Read through texel buffers (gathers on CPU devices, the texture cache on GPUs).
layout(set = 0, binding = 1) uniform samplerBuffer weights;    // per reference, panorama
layout(set = 0, binding = 2) uniform usamplerBuffer warped;    // per reference, matching
layout(set = 0, binding = 3) uniform samplerBuffer original;   // per reference, matching
layout(set = 0, binding = 4) uniform usamplerBuffer colour;    // per reference, colour
layout(std430, set = 0, binding = 5) writeonly buffer OutColour { uint out_colour[]; };
layout(std430, set = 0, binding = 6) writeonly buffer OutDistance { float out_distance[]; };
layout(push_constant) uniform Push {
  uint width;
  uint height;
  uint references;
} push;

const uint kEmpty = 0xffffffffu;

// Bilinear over the taps that hold a value; false when none does.
bool sample_warped(uint k, Camera c, vec2 uv, out float value) {
  const vec2 f = floor(uv);
  const vec2 t = uv - f;
  float sum = 0.0, total = 0.0;
  for (int j = 0; j < 4; ++j) {
    const ivec2 q = ivec2(f) + ivec2(j & 1, j >> 1);
    if (q.x < 0 || q.y < 0 || q.x >= int(c.width) || q.y >= int(c.height)) continue;
    const uint bits = texelFetch(warped, int(k * c.width * c.height + uint(q.y) * c.width + uint(q.x))).x;
    if (bits == kEmpty) continue;
    const float w = ((j & 1) != 0 ? t.x : 1.0 - t.x) * ((j >> 1) != 0 ? t.y : 1.0 - t.y);
    sum += w * uintBitsToFloat(bits);
    total += w;
  }
  value = total > 0.0 ? sum / total : 0.0;
  return total > 0.0;
}

float sample_original(uint k, Camera c, vec2 uv) {
  const vec2 f = floor(uv);
  const vec2 t = uv - f;
  float v[4];
  for (int j = 0; j < 4; ++j) {
    const ivec2 q = clamp(ivec2(f) + ivec2(j & 1, j >> 1), ivec2(0), ivec2(c.width, c.height) - 1);
    v[j] = texelFetch(original, int(k * c.width * c.height + uint(q.y) * c.width + uint(q.x))).x;
  }
  return mix(mix(v[0], v[1], t.x), mix(v[2], v[3], t.x), t.y);
}

vec3 sample_colour(uint k, Camera c, vec2 uv) {
  const vec2 f = floor(uv);
  const vec2 t = uv - f;
  vec3 v[4];
  for (int j = 0; j < 4; ++j) {
    const ivec2 q = clamp(ivec2(f) + ivec2(j & 1, j >> 1), ivec2(0), ivec2(c.width, c.height) - 1);
    v[j] = unpack_rgb(texelFetch(colour, int(k * c.width * c.height + uint(q.y) * c.width + uint(q.x))).x);
  }
  return mix(mix(v[0], v[1], t.x), mix(v[2], v[3], t.x), t.y);
}

void main() {
  const uvec2 p = gl_GlobalInvocationID.xy;
  if (p.x >= push.width || p.y >= push.height) return;
  const uint pixel = p.y * push.width + p.x;
  const float phi = (float(p.y) + 0.5) * kPi / float(push.height) - 0.5 * kPi;
  const float theta = (float(p.x) + 0.5) * 2.0 * kPi / float(push.width) + kPi;
  const vec3 dir = vec3(cos(phi) * sin(theta), sin(phi), cos(phi) * cos(theta));
  float weight_sum = 0.0, inverse_sum = 0.0;
  vec3 rgb = vec3(0.0);
  for (uint k = 0u; k < push.references; ++k) {
    const Camera c = cameras[2u * k];
    const Camera colour_camera = cameras[2u * k + 1u];
    const float w = texelFetch(weights, int(k * push.width * push.height + pixel)).x;
    const vec3 dir_c = vec3(dot(c.row0.xyz, dir), dot(c.row1.xyz, dir), dot(c.row2.xyz, dir));
    const vec3 t_c = vec3(c.row0.w, c.row1.w, c.row2.w);
    vec2 uv;
    project_source(c, dir_c, uv);
    uv = clamp(uv, vec2(0.1), vec2(c.width, c.height) - 1.1);
    float r;
    if (!(w > 0.0) || !sample_warped(k, c, uv, r) || !(r > 0.0)) continue;
    weight_sum += w;
    inverse_sum += w / r;
    const float d = min(r, sample_original(k, c, uv));
    vec3 ray;
    vec2 colour_uv;
    if (unproject_source(c, uv, ray) && project_source(colour_camera, d * ray + t_c, colour_uv)) {
      rgb += w * sample_colour(k, colour_camera, colour_uv);
    }
  }
  out_distance[pixel] = weight_sum > 0.0 ? weight_sum / inverse_sum : 0.0;
  const uvec3 v = uvec3(clamp(floor(rgb / max(weight_sum, 1e-20) + 0.5), 0.0, 255.0));
  out_colour[pixel] = pack_rgb(v);
}
