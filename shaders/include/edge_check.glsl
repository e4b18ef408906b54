// Shared by edge_marks.comp and edge_check.comp (server/stitch/edge_check.h): their push
// constants and the block grid.

layout(push_constant) uniform Push {
  uint width;
  uint height;
  int block;   // pixels per side of a block
  int reach;   // blocks
  float step;  // m^-1
  float color; // levels
  float factor;
} push;

int blocks_x() { return (int(push.width) + push.block - 1) / push.block; }
int blocks_y() { return (int(push.height) + push.block - 1) / push.block; }
