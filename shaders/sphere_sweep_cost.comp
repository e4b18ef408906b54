#version 450
#extension GL_GOOGLE_include_directive : require
#ifdef VOLUME_F16
#extension GL_EXT_shader_16bit_storage : require
#endif
// Sphere sweep and matching cost (ALGORITHM.md §3 steps 1 and 3): for each reference pixel and
// candidate distance d_i (uniform in inverse distance), sample the selected camera bilinearly
// at the projection of ray * d_i (taps outside the image read 0) and store the L1 colour
// difference (0-255 per channel, summed) clamped at 500. Pixels without a selected camera get
// cost 0 for every candidate. Every reference of the group in one dispatch: z is the slot.
//
// kCost (DepthOptions::cost) chooses the cost. 0: the paper's, above, on the camera images. The
// others read the matching features instead (matching_features.comp) and interpolate their
// per-tap differences bilinearly: 1, the L1 difference of the normalised colours; 2, the Hamming
// distance of the census bytes (x census_scale); 3, their sum; 4, as 1 on the ratio features.
layout(local_size_x_id = 100, local_size_y_id = 101, local_size_z_id = 102) in;
layout(constant_id = 30) const uint kCost = 0u;
// DepthOptions::match_cameras: 2 also matches against the second camera (selection plane
// slots + reference), where there is one, and stores the mean of the two costs.
layout(constant_id = 31) const uint kCameras = 1u;
// DepthOptions::confident_sigma_s > 0: also the confidence of each pixel's raw cost curve
// (wta.glsl), as the fourth byte of its filter guide (binding 4, plane `first + slot`), which
// sets the ISB filter's spatial sigma there (isb_weights.glsl).
layout(constant_id = 32) const bool kConfidenceToGuide = false;

#include "camera.glsl"
#include "pixels.glsl"
#include "volume.glsl"
#include "isb_weights.glsl"
#include "wta.glsl"

// Per reference (first + slot): num_cameras records, the reference's frame to each camera's.
CAMERA_RECORDS(0)
// RGBA8 texels, camera-major: the images (kCost 0) or their matching features.
layout(set = 0, binding = 1) uniform usamplerBuffer images;
layout(std430, set = 0, binding = 2) readonly buffer Selection { int selection[]; };  // per reference
layout(std430, set = 0, binding = 3) writeonly buffer Volume { VOLUME_T v[]; } volume[kMaxChunks];
layout(std430, set = 0, binding = 4) buffer Guide { uint guide[]; };
layout(push_constant) uniform Push {
  uint width;
  uint height;
  uint num_cameras;
  uint first;  // the group's first reference: slot s is reference first + s
  uint num_candidates;
  float inv_d_min;
  float inv_d_max;
  float census_scale;
  uint slots;           // reference slots in all (the second cameras' planes follow theirs)
  uint references[8];  // the camera of each reference
} push;

vec3 tap(uint camera, int x, int y) {
  if (x < 0 || y < 0 || x >= int(push.width) || y >= int(push.height)) return vec3(0.0);
  return unpack_rgb(texelFetch(images, int((camera * push.height + uint(y)) * push.width + uint(x))).x);
}

vec3 bilinear(uint camera, vec2 uv) {
  if (uv.x < -2.0 || uv.y < -2.0 || uv.x > float(push.width) + 1.0 || uv.y > float(push.height) + 1.0) {
    return vec3(0.0);
  }
  const vec2 f = floor(uv);
  const vec2 t = uv - f;
  const int x = int(f.x), y = int(f.y);
  return mix(mix(tap(camera, x, y), tap(camera, x + 1, y), t.x),
             mix(tap(camera, x, y + 1), tap(camera, x + 1, y + 1), t.x), t.y);
}

// The robust costs: the differences of the four taps to the reference's features, bilinearly.
float feature_difference(uint features, uint reference) {
  const vec3 d = abs(unpack_rgb(features) - unpack_rgb(reference));
  const float census = float(bitCount((features ^ reference) >> 24));
  if (kCost == 1u || kCost == 4u) return d.x + d.y + d.z;
  if (kCost == 2u) return census * push.census_scale;
  return d.x + d.y + d.z + census * push.census_scale;
}

float tap_difference(uint camera, int x, int y, uint reference) {
  if (x < 0 || y < 0 || x >= int(push.width) || y >= int(push.height)) return 500.0;
  return feature_difference(texelFetch(images, int((camera * push.height + uint(y)) * push.width + uint(x))).x,
                            reference);
}

float bilinear_difference(uint camera, vec2 uv, uint reference) {
  if (uv.x < -2.0 || uv.y < -2.0 || uv.x > float(push.width) + 1.0 || uv.y > float(push.height) + 1.0) {
    return 500.0;
  }
  const vec2 f = floor(uv);
  const vec2 t = uv - f;
  const int x = int(f.x), y = int(f.y);
  return mix(mix(tap_difference(camera, x, y, reference), tap_difference(camera, x + 1, y, reference), t.x),
             mix(tap_difference(camera, x, y + 1, reference), tap_difference(camera, x + 1, y + 1, reference), t.x),
             t.y);
}

// The cost of candidate i (0 past the last candidate: padding).
float candidate_cost(uint i, Camera c, vec3 rotated, vec3 translation, int selected,
                     uint reference, float step) {
  if (i >= push.num_candidates) return 0.0;
  const float distance_i = 1.0 / (push.inv_d_min + step * float(i));
  vec2 uv;
  if (kCost != 0u) {
    const bool seen = project_source(c, distance_i * rotated + translation, uv);
    return min(seen ? bilinear_difference(uint(selected), uv, reference) : 500.0, 500.0);
  }
  const vec3 reference_rgb = unpack_rgb(reference);
  vec3 rgb = vec3(0.0);
  if (project_source(c, distance_i * rotated + translation, uv)) rgb = bilinear(uint(selected), uv);
  const vec3 d = abs(rgb - reference_rgb);
  return min(d.x + d.y + d.z, 500.0);
}

void main() {
  const uvec3 g = gl_GlobalInvocationID;
  if (g.x >= push.width || g.y >= push.height) return;
  const uint slot = g.z, reference = push.first + slot;
  const uint plane = push.width * push.height, pixel = g.y * push.width + g.x;
  const uint camera = push.references[reference];
  const int selected = selection[reference * plane + pixel];
  vec3 ray = vec3(0.0);
  const uint records = reference * push.num_cameras;
  const bool matching = selected >= 0 && unproject_source(cameras[records + camera], vec2(g.xy), ray);
  const uint reference_texel = texelFetch(images, int(camera * plane + pixel)).x;
  const float step = (push.inv_d_max - push.inv_d_min) / float(push.num_candidates - 1u);
  // What does not change with the candidate, once per pixel: the selected camera and the ray in
  // its axes (the point at distance d is d * rotated + translation).
  const Camera c = cameras[records + uint(max(selected, 0))];
  const vec3 rotated = vec3(dot(c.row0.xyz, ray), dot(c.row1.xyz, ray), dot(c.row2.xyz, ray));
  const vec3 translation = vec3(c.row0.w, c.row1.w, c.row2.w);
  const int second = kCameras > 1u ? selection[(push.slots + reference) * plane + pixel] : -1;
  const Camera c2 = cameras[records + uint(max(second, 0))];
  const vec3 rotated2 = vec3(dot(c2.row0.xyz, ray), dot(c2.row1.xyz, ray), dot(c2.row2.xyz, ray));
  const vec3 translation2 = vec3(c2.row0.w, c2.row1.w, c2.row2.w);
  // Pixels that match loop over the candidates, a texel (kPack of them) at a time; the rest
  // (outside the lens or the masks) only store zeros, so a CPU device skips the sweep where a
  // whole vector of pixels has no match.
  const uint matched = matching ? (push.num_candidates + kPack - 1u) / kPack : 0u;
  uint t = 0u;
  Wta wta;
  Peaks peaks;
  for (; t < matched; ++t) {
#if VOLUME_PACK == 4
    VOLUME_V cost = vec4(candidate_cost(4u * t, c, rotated, translation, selected, reference_texel, step),
                         candidate_cost(4u * t + 1u, c, rotated, translation, selected, reference_texel, step),
                         candidate_cost(4u * t + 2u, c, rotated, translation, selected, reference_texel, step),
                         candidate_cost(4u * t + 3u, c, rotated, translation, selected, reference_texel, step));
    if (second >= 0) {
      cost = 0.5 * (cost + vec4(candidate_cost(4u * t, c2, rotated2, translation2, second, reference_texel, step),
                                candidate_cost(4u * t + 1u, c2, rotated2, translation2, second, reference_texel, step),
                                candidate_cost(4u * t + 2u, c2, rotated2, translation2, second, reference_texel, step),
                                candidate_cost(4u * t + 3u, c2, rotated2, translation2, second, reference_texel, step)));
    }
#else
    VOLUME_V cost = candidate_cost(t, c, rotated, translation, selected, reference_texel, step);
    if (second >= 0)
      cost = 0.5 * (cost + candidate_cost(t, c2, rotated2, translation2, second, reference_texel, step));
#endif
    volume[t / kTexels].v[volume_index(slot, t % kTexels, plane, pixel)] = VOLUME_T(cost);
    if (kConfidenceToGuide) winner_texel(wta, peaks, t * kPack, push.num_candidates, cost);
  }
  if (kConfidenceToGuide) {
    const float confidence = matched > 0u ? peaks_confidence(peaks, wta, push.num_candidates) : 0.0;
    const uint at = reference * plane + pixel;
    guide[at] = (guide[at] & 0x00ffffffu) | (confidence_byte(confidence) << 24u);
  }
  for (; t < kChunks * kTexels; ++t)
    volume[t / kTexels].v[volume_index(slot, t % kTexels, plane, pixel)] = VOLUME_T(0.0);
}
