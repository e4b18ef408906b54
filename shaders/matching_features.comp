#version 450
#extension GL_GOOGLE_include_directive : require
// Matching features of every camera image, for the costs that must not depend on a camera's
// gain, colour cast or vignetting (DepthOptions::cost other than kAbsoluteDifference). One RGBA8
// texel per pixel:
// - RGB, nad (push.ratio 0): each channel normalised by the statistics of its
//   (2 radius + 1)^2 window, 128 + 32 (I - mean) / (std + epsilon), clamped to [0, 255]: a gain,
//   a cast or a smooth vignetting multiplies I, mean and std alike and leaves it unchanged (up to
//   epsilon).
// - RGB, ratio (push.ratio 1): each channel over its neighbourhood's mean,
//   128 I / (mean + epsilon), clamped to [0, 255]. The mean is Gaussian (sigma radius / 2) over
//   9 x 9 taps k radius / 4 (integer division) from the pixel, of usable pixels only (the
//   cameras' usable masks): the black beyond the image circle and the rig's own parts would
//   otherwise pull the mean down near them, differently in every camera. A gain, a cast or a
//   vignetting smooth over the window cancels; the contrast, unlike nad's, is not raised to unit
//   deviation, so the noise of plain surfaces stays small.
// - A: an 8-bit census of the luminance: bit k set where the neighbour at census_radius in
//   direction k (E, NE, N, NW, W, SW, S, SE) is brighter than the pixel by more than 1 level.
// z is the camera.
layout(local_size_x_id = 100, local_size_y_id = 101, local_size_z_id = 102) in;

#include "pixels.glsl"

layout(set = 0, binding = 0) uniform usamplerBuffer images;  // RGBA8 texels, camera-major
layout(std430, set = 0, binding = 1) writeonly buffer Features { uint features[]; };
// Usable masks, bytes, camera-major (read by the ratio mode only).
layout(std430, set = 0, binding = 2) readonly buffer Masks { uint masks[]; };
layout(push_constant) uniform Push {
  uint width;
  uint height;
  int radius;
  int census_radius;
  float epsilon;
  uint ratio;
} push;

// The index of pixel (x, y), clamped to the image, of the camera starting at `base`.
uint index_at(uint base, int x, int y) {
  x = clamp(x, 0, int(push.width) - 1);
  y = clamp(y, 0, int(push.height) - 1);
  return base + uint(y) * push.width + uint(x);
}

vec3 rgb_at(uint base, int x, int y) {
  return unpack_rgb(texelFetch(images, int(index_at(base, x, y))).x);
}

float luma(vec3 rgb) { return dot(rgb, vec3(0.299, 0.587, 0.114)); }

void main() {
  const uvec3 g = gl_GlobalInvocationID;
  if (g.x >= push.width || g.y >= push.height) return;
  const uint plane = push.width * push.height, base = g.z * plane;
  const int x = int(g.x), y = int(g.y);
  const vec3 centre = rgb_at(base, x, y);
  vec3 normalised;
  if (push.ratio != 0u) {
    vec3 sum = vec3(0.0);
    float weights = 0.0;
    for (int ky = -4; ky <= 4; ++ky) {
      for (int kx = -4; kx <= 4; ++kx) {
        // Integer division truncates towards 0 in GLSL and C++ alike (ratio_features_cpu).
        const uint i = index_at(base, x + kx * push.radius / 4, y + ky * push.radius / 4);
        const float w = BYTE_AT(masks, i) != 0u ? exp(-float(kx * kx + ky * ky) / 8.0) : 0.0;
        sum += w * unpack_rgb(texelFetch(images, int(i)).x);
        weights += w;
      }
    }
    const vec3 mean = weights > 0.0 ? sum / weights : centre;
    normalised = clamp(128.0 * centre / (mean + push.epsilon), vec3(0.0), vec3(255.0));
  } else {
    vec3 sum = vec3(0.0), sum2 = vec3(0.0);
    for (int dy = -push.radius; dy <= push.radius; ++dy) {
      for (int dx = -push.radius; dx <= push.radius; ++dx) {
        const vec3 v = rgb_at(base, x + dx, y + dy);
        sum += v;
        sum2 += v * v;
      }
    }
    const float n = float((2 * push.radius + 1) * (2 * push.radius + 1));
    const vec3 mean = sum / n;
    const vec3 deviation = sqrt(max(sum2 / n - mean * mean, vec3(0.0)));
    normalised = clamp(128.0 + 32.0 * (centre - mean) / (deviation + push.epsilon), vec3(0.0),
                       vec3(255.0));
  }

  const float c = luma(centre) + 1.0;
  const int r = push.census_radius;
  uint census = 0u;
  census |= luma(rgb_at(base, x + r, y)) > c ? 1u : 0u;
  census |= luma(rgb_at(base, x + r, y - r)) > c ? 2u : 0u;
  census |= luma(rgb_at(base, x, y - r)) > c ? 4u : 0u;
  census |= luma(rgb_at(base, x - r, y - r)) > c ? 8u : 0u;
  census |= luma(rgb_at(base, x - r, y)) > c ? 16u : 0u;
  census |= luma(rgb_at(base, x - r, y + r)) > c ? 32u : 0u;
  census |= luma(rgb_at(base, x, y + r)) > c ? 64u : 0u;
  census |= luma(rgb_at(base, x + r, y + r)) > c ? 128u : 0u;
  features[base + g.y * push.width + g.x] = pack_rgb(uvec3(floor(normalised + 0.5))) | (census << 24);
}
