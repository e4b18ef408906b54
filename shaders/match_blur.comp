#version 450
// The matching images' Gaussian blur (DepthOptions::match_blur; server/depth/match_blur.h): each
// camera's packed RGBA8 image from `source` into `blurred`, separably, with 2 r + 1 taps of the
// weights in push.weights (w[|i|] for offset i, r = push.radius <= kMaxRadius), coordinates
// clamped to the image (its edge repeated). One workgroup per 16 x 16 pixels: it loads its tile
// and r pixels around it once, sums along rows into shared memory, then along columns, and rounds
// (alpha is the centre pixel's). Sums run from -r to r, `precise` so that no multiply-add is
// fused: match_blur_cpu is the CPU check, in the same float order.
layout(local_size_x_id = 100, local_size_y_id = 101, local_size_z_id = 102) in;

layout(std430, set = 0, binding = 0) readonly buffer Source { uint source[]; };  // image by image
layout(std430, set = 0, binding = 1) writeonly buffer Blurred { uint blurred[]; };
layout(push_constant) uniform Push {
  uint width;
  uint height;
  uint images;
  uint radius;
  float weights[9];  // kMaxRadius + 1
} push;

const uint kTile = 16u;  // the workgroup (set by the host)
const uint kMaxRadius = 8u;  // kMatchBlurMaxRadius (server/depth/depth_options.h)
const uint kSpan = kTile + 2u * kMaxRadius;
shared uint pixels[kSpan * kSpan];      // the tile and its rim, packed RGBA8
shared vec3 rows[kSpan * kTile];        // after the row pass: kSpan rows of kTile columns

// The 8-bit channels as exact floats.
vec3 channels(uint rgba) {
  return vec3(float(rgba & 0xffu), float((rgba >> 8) & 0xffu), float((rgba >> 16) & 0xffu));
}

void main() {
  const uint r = push.radius;
  const uint span = kTile + 2u * r;
  const uvec2 origin = gl_WorkGroupID.xy * kTile;
  const uint image = gl_WorkGroupID.z;
  const uint base = image * push.width * push.height;
  const uint local = gl_LocalInvocationID.y * kTile + gl_LocalInvocationID.x;
  // The tile and its rim, edge pixels repeated.
  for (uint k = local; k < span * span; k += kTile * kTile) {
    const int x = clamp(int(origin.x) + int(k % span) - int(r), 0, int(push.width) - 1);
    const int y = clamp(int(origin.y) + int(k / span) - int(r), 0, int(push.height) - 1);
    pixels[k] = source[base + uint(y) * push.width + uint(x)];
  }
  barrier();
  // Rows: every row of the span, the tile's columns.
  for (uint k = local; k < span * kTile; k += kTile * kTile) {
    const uint row = k / kTile, column = k % kTile;
    precise vec3 sum = vec3(0.0);
    for (uint i = 0u; i <= 2u * r; ++i) {
      const float w = push.weights[i >= r ? i - r : r - i];
      precise vec3 tap = w * channels(pixels[row * span + column + i]);
      sum += tap;
    }
    rows[k] = sum;
  }
  barrier();
  const uvec2 p = origin + gl_LocalInvocationID.xy;
  if (p.x >= push.width || p.y >= push.height || image >= push.images) return;
  precise vec3 sum = vec3(0.0);
  for (uint i = 0u; i <= 2u * r; ++i) {
    const float w = push.weights[i >= r ? i - r : r - i];
    precise vec3 tap = w * rows[(gl_LocalInvocationID.y + i) * kTile + gl_LocalInvocationID.x];
    sum += tap;
  }
  const uint alpha = pixels[(gl_LocalInvocationID.y + r) * span + gl_LocalInvocationID.x + r] &
                     0xff000000u;
  const uvec3 c = uvec3(clamp(floor(sum + 0.5), vec3(0.0), vec3(255.0)));
  blurred[base + p.y * push.width + p.x] = c.r | (c.g << 8) | (c.b << 16) | alpha;
}
