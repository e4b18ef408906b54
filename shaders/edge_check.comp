#version 450
#extension GL_GOOGLE_include_directive : require
// Edge check, second pass (server/stitch/edge_check.h, docs/accuracy.md): a pixel within `reach`
// blocks of a block edge_marks.comp marked (columns wrapping, rows clamped) has its confidence
// multiplied by `factor`, in place. edge_check_cpu is the CPU check: keep the two in step.
layout(local_size_x_id = 100, local_size_y_id = 101, local_size_z_id = 102) in;

layout(std430, set = 0, binding = 0) readonly buffer Marks { uint marks[]; };
layout(std430, set = 0, binding = 1) buffer Confidence { float confidence[]; };
#include "edge_check.glsl"

void main() {
  const ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  const int w = int(push.width), h = int(push.height);
  if (p.x >= w || p.y >= h) return;
  const int bx = p.x / push.block, by = p.y / push.block, nx = blocks_x(), ny = blocks_y();
  bool near = false;
  for (int y = max(0, by - push.reach); y <= min(ny - 1, by + push.reach) && !near; ++y) {
    for (int dx = -push.reach; dx <= push.reach; ++dx) {
      int x = bx + dx;
      while (x < 0) x += nx;  // GLSL's % is undefined for negative operands
      if (marks[uint(y * nx + x % nx)] != 0u) {
        near = true;
        break;
      }
    }
  }
  if (near) {
    const uint i = uint(p.y * w + p.x);
    confidence[i] *= push.factor;
  }
}
