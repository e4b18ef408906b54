#version 450
#extension GL_GOOGLE_include_directive : require
// Merge into the panorama (ALGORITHM.md §5 step 4). For each reference c, the panorama
// direction in c's axes gives uv (clamped to [0.1, W - 1.1] x [0.1, H - 1.1]); r is the warped and
// inpainted distance there (bilinear over the taps that hold a value), accumulated as weight / r.
// Colour: d' = min(r, original distance at uv), P = d' ray(uv) + t_c, and the colour image (at
// its own resolution) is sampled bilinearly at project(P). Output distance = 1 / sum(weight / r)
// over the references that had a value (weights renormalised); 0 where none had.
// Confidence in [0, 1] (docs/accuracy.md, "Confidence"): per reference, the confidence of the
// source pixel the warped point came from (its cost curve's, when the caller has them, else 1),
// times how well that source pixel's own distance agrees with the point,
// exp(-(|1/|P| - 1/d_source| / tolerance)^2), which is near 0 where the warp inpainted a hole
// (the point lies behind what the source saw there); blended with the weights, then times
// exp(-(spread / tolerance)^2), where spread is twice the weighted standard deviation of the
// references' inverse distances (where references overlap, their agreement). 0 where no value.
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
layout(set = 0, binding = 7) uniform samplerBuffer confidence;  // per reference, matching
layout(std430, set = 0, binding = 8) writeonly buffer OutConfidence { float out_confidence[]; };
layout(push_constant) uniform Push {
  uint width;
  uint height;
  uint references;
  uint has_confidence;  // whether `confidence` holds the references' cost confidences
  float tolerance;      // inverse distance, 1/m
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

// Reference k's value nearest to uv in a per-reference matching-resolution plane.
float nearest(samplerBuffer plane, uint k, Camera c, vec2 uv) {
  const ivec2 q = clamp(ivec2(floor(uv + 0.5)), ivec2(0), ivec2(c.width, c.height) - 1);
  return texelFetch(plane, int(k * c.width * c.height + uint(q.y) * c.width + uint(q.x))).x;
}

// How far the warped point (d_c = r ray + t_c in c's frame) is from what c saw in its direction.
float source_agreement(uint k, Camera c, vec3 d_c, out float source_confidence) {
  vec2 source_uv;
  source_confidence = 0.0;
  if (!project_source(c, d_c, source_uv)) return 0.0;
  source_confidence = push.has_confidence != 0u ? nearest(confidence, k, c, source_uv) : 1.0;
  const float seen = nearest(original, k, c, source_uv);
  const float miss = abs(1.0 / max(length(d_c), 1e-6) - 1.0 / max(seen, 1e-6)) / push.tolerance;
  return exp(-miss * miss);
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
  float weight_sum = 0.0, inverse_sum = 0.0, inverse_sq_sum = 0.0, confidence_sum = 0.0;
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
    inverse_sq_sum += w / (r * r);
    const float d = min(r, sample_original(k, c, uv));
    vec3 ray;
    vec2 colour_uv;
    if (unproject_source(c, uv, ray)) {
      if (project_source(colour_camera, d * ray + t_c, colour_uv))
        rgb += w * sample_colour(k, colour_camera, colour_uv);
      float source_confidence;
      const float agreement = source_agreement(k, c, r * ray + t_c, source_confidence);
      confidence_sum += w * source_confidence * agreement;
    }
  }
  out_distance[pixel] = weight_sum > 0.0 ? weight_sum / inverse_sum : 0.0;
  float merged_confidence = 0.0;
  if (weight_sum > 0.0) {
    const float mean = inverse_sum / weight_sum;
    const float spread = 2.0 * sqrt(max(inverse_sq_sum / weight_sum - mean * mean, 0.0)) / push.tolerance;
    merged_confidence = clamp(confidence_sum / weight_sum * exp(-spread * spread), 0.0, 1.0);
  }
  out_confidence[pixel] = merged_confidence;
  const uvec3 v = uvec3(clamp(floor(rgb / max(weight_sum, 1e-20) + 0.5), 0.0, 255.0));
  out_colour[pixel] = pack_rgb(v);
}
