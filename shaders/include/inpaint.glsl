// Shared by the directional inpainting kernels (ALGORITHM.md §5 step 2): each pixel's two
// background-side neighbours, chosen once per pose by inpaint_directions.comp.

struct Direction {
  uint codes;  // neighbour index (0-7) of the first choice | second << 8; 0xff: none
  float weight0;
  float weight1;
  uint unused;
};

// Direction records are read through a texel buffer of RGBA32UI texels (one gather of the whole
// record where a storage-buffer load would fetch its four words lane by lane on a CPU device).
Direction direction_at(usamplerBuffer records, int index) {
  const uvec4 v = texelFetch(records, index);
  return Direction(v.x, uintBitsToFloat(v.y), uintBitsToFloat(v.z), v.w);
}

// Whether a direction record names any neighbour: pixels without one (outside the target's
// valid rays) can never be filled.
bool has_neighbour(Direction d) { return (d.codes & 0xffu) <= 7u; }

// Neighbour offsets by code 0-7: (1, 0), (1, 1), (0, 1), (-1, 1), (-1, 0), (-1, -1), (0, -1),
// (1, -1), i.e. counter-clockwise from +x. Packed as 2 bits of dx + 1 and dy + 1 per code and
// unpacked by shifts (a constant array indexed at run time would sit in per-lane memory on a CPU
// device).
const uint kNeighbourDx = 0x901Au;  // dx + 1 of codes 7..0: 2 1 0 0 0 1 2 2
const uint kNeighbourDy = 0x01A9u;  // dy + 1 of codes 7..0: 0 0 0 1 2 2 2 1
ivec2 neighbour_offset(uint code) {
  return ivec2(int((kNeighbourDx >> (2u * code)) & 3u), int((kNeighbourDy >> (2u * code)) & 3u)) - 1;
}

// Index of neighbour k (0 or 1) of pixel q in `d`, or -1 when there is none or it lies outside
// the image (panoramas wrap around horizontally when wrap_x is set).
int inpaint_neighbour(Direction d, uint k, uvec2 q, uint width, uint height, uint wrap_x) {
  const uint code = (d.codes >> (8u * k)) & 0xffu;
  if (code > 7u) return -1;
  ivec2 n = ivec2(q) + neighbour_offset(code);
  if (wrap_x != 0u) n.x = (n.x + int(width)) % int(width);
  if (n.x < 0 || n.y < 0 || n.x >= int(width) || n.y >= int(height)) return -1;
  return n.y * int(width) + n.x;
}
