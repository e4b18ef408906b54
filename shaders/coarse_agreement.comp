#version 450
#extension GL_GOOGLE_include_directive : require
// The confidence's coarse agreement (docs/accuracy.md, "Confidence"): where a pixel's distance
// disagrees with the winner of its neighbourhood's filtered cost curve, the filter's smoothing
// biased it (slanted surfaces, thin structures). One invocation per block of 4 x 4 pixels of the
// ISB filter's level 1 (8 x 8 pixels of the distance map), in two passes:
// - `apply` 0, right after a group's filter: the level's filtered curves summed over the block in
//   row order (pixels outside the level left out), and their winner's inverse distance
//   (wta.glsl) into `block_map`;
// - `apply` 1, once the distance map is final (after the post-filter, which the comparison
//   needs): each of the block's pixels' confidence times exp(-(delta / tolerance)^2), delta the
//   difference between its inverse distance and the block winners' interpolated bilinearly
//   between block centres.
// z is the slot; its distances and confidences are plane first + z of `distance_map` and
// `confidence_map`, its blocks plane first + z of `block_map`.
layout(local_size_x_id = 100, local_size_y_id = 101, local_size_z_id = 102) in;

#include "volume.glsl"
#include "wta.glsl"

layout(set = 0, binding = 0) uniform samplerBuffer volume[kMaxChunks];  // the filter's level 1
layout(std430, set = 0, binding = 1) readonly buffer Distance { float distance_map[]; };
layout(std430, set = 0, binding = 2) buffer Confidence { float confidence_map[]; };
layout(std430, set = 0, binding = 3) buffer Blocks { float block_map[]; };
layout(push_constant) uniform Push {
  uint width;  // the distance map
  uint height;
  uint level_width;  // the filter's level 1
  uint level_height;
  uint num_candidates;
  float inv_d_min;
  float inv_d_max;
  float d_max;
  uint first;
  float inv_tolerance;  // 1 / tolerance, m
  uint apply;
} push;

const uint kBlock = 4u;  // level-1 pixels per block side

// The block's summed candidates of one chunk into `wta`.
void block_chunk(samplerBuffer chunk_texels, uint chunk, uint slot, uvec2 block, inout Wta wta,
                 inout Peaks peaks) {
  const uint plane = push.level_width * push.level_height;
  const uint x_end = min(block.x * kBlock + kBlock, push.level_width);
  const uint y_end = min(block.y * kBlock + kBlock, push.level_height);
  for (uint t = 0u; t < kTexels; ++t) {
    VOLUME_V sum = VOLUME_V(0.0);
    for (uint y = block.y * kBlock; y < y_end; ++y)
      for (uint x = block.x * kBlock; x < x_end; ++x)
        sum += VOLUME_FETCH(chunk_texels, int(volume_index(slot, t, plane, y * push.level_width + x)));
    winner_texel(wta, peaks, chunk * kChannels + t * kPack, push.num_candidates, sum);
  }
}

void main() {
  const uvec3 g = gl_GlobalInvocationID;
  if (g.x * kBlock >= push.level_width || g.y * kBlock >= push.level_height) return;
  const uint blocks_x = (push.level_width + kBlock - 1u) / kBlock;
  const uint blocks = blocks_x * ((push.level_height + kBlock - 1u) / kBlock);
  const uint block_at = (push.first + g.z) * blocks + g.y * blocks_x + g.x;
  if (push.apply == 0u) {
    Wta wta;
    Peaks peaks;
#define BLOCK_CHUNK(c) \
  if (uint(c) < kChunks) block_chunk(volume[c], uint(c), g.z, g.xy, wta, peaks);
    FOR_EACH_CHUNK(BLOCK_CHUNK)
    block_map[block_at] =
        1.0 / wta_distance(wta, push.num_candidates, push.inv_d_min, push.inv_d_max, push.d_max);
    return;
  }
  // The blocks' winners interpolated bilinearly between block centres (clamped at the edges),
  // so that the factor has no steps at block borders.
  const uint blocks_y = blocks / blocks_x, block_first = (push.first + g.z) * blocks;
  const uint plane = push.width * push.height;
  const uint x_end = min(g.x * 2u * kBlock + 2u * kBlock, push.width);
  const uint y_end = min(g.y * 2u * kBlock + 2u * kBlock, push.height);
  for (uint y = g.y * 2u * kBlock; y < y_end; ++y) {
    const float v = max((float(y) + 0.5) / float(2u * kBlock) - 0.5, 0.0);
    const uint y0 = min(uint(v), blocks_y - 1u), y1 = min(y0 + 1u, blocks_y - 1u);
    const float fy = min(v - float(y0), 1.0);
    for (uint x = g.x * 2u * kBlock; x < x_end; ++x) {
      const float u = max((float(x) + 0.5) / float(2u * kBlock) - 0.5, 0.0);
      const uint x0 = min(uint(u), blocks_x - 1u), x1 = min(x0 + 1u, blocks_x - 1u);
      const float fx = min(u - float(x0), 1.0);
      const float top = mix(block_map[block_first + y0 * blocks_x + x0],
                            block_map[block_first + y0 * blocks_x + x1], fx);
      const float bottom = mix(block_map[block_first + y1 * blocks_x + x0],
                               block_map[block_first + y1 * blocks_x + x1], fx);
      const float block_inverse = mix(top, bottom, fy);
      const uint at = (push.first + g.z) * plane + y * push.width + x;
      const float delta = (1.0 / distance_map[at] - block_inverse) * push.inv_tolerance;
      confidence_map[at] *= exp(-delta * delta);
    }
  }
}
