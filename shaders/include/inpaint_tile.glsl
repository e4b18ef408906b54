// Up to kHalo passes of directional inpainting (ALGORITHM.md §5 step 2) in one dispatch, exactly
// as that many ping-pong passes over the whole image: each workgroup loads its kTile x kTile
// pixels and a halo of kHalo around them into shared memory and runs the passes there. A pass
// reads only 8-neighbours, so after p passes the outer p rings of the loaded region are stale and
// the tile itself is exact after kHalo. One dispatch replaces kHalo, so the image is read and
// written once per kHalo passes instead of once per pass. A tile without holes skips the passes,
// and a pass that changes nothing in the region ends them (every later pass would repeat it). A
// tile without holes it could fill (empty pixels that have a direction) is copied through first,
// without its halo and without shared memory: most tiles are.
// The workgroup's z is the layer: plane z of the directions, source and destination.
//
// The including shader declares the texel buffers `directions` (inpaint.glsl) and `source`, the
// storage buffers Destination `destination` and Filled `filled` and the push constants (width, height, wrap_x, pass,
// passes), and defines, before including this file:
//   bool is_empty(uint value);
//   uint blend(uint v0, float w0, uint v1, float w1);  // a neighbour with w = 0 is absent
//   const uint kEmptyValue;

const uint kHalo = 8u;
layout(constant_id = 0) const uint kTile = 32u;  // chosen by the host to fit shared memory
const uint kRegion = kTile + 2u * kHalo;
const uint kRegionPixels = kRegion * kRegion;

shared uint tile_values[2u * kRegionPixels];
// Whether pass p changed anything in the region, in slot p % 3 (three slots, so a slot is reset
// only when no invocation can still read or write it); slot 0 first says whether the tile has a
// hole to fill at all.
shared uint tile_changed[3];

bool in_tile(uvec2 r) {
  return r.x >= kHalo && r.y >= kHalo && r.x < kHalo + kTile && r.y < kHalo + kTile;
}

// The image pixel under region pixel r (wrapped horizontally for panoramas); false outside.
bool image_pixel(uvec2 r, out ivec2 g) {
  g = ivec2(gl_WorkGroupID.xy * kTile) - int(kHalo) + ivec2(r);
  if (push.wrap_x != 0u) g.x = (g.x % int(push.width) + int(push.width)) % int(push.width);
  return g.x >= 0 && g.y >= 0 && g.x < int(push.width) && g.y < int(push.height);
}

void inpaint_tile() {
  const int layer_base = int(gl_WorkGroupID.z * push.width * push.height);
  const uint threads = gl_WorkGroupSize.x * gl_WorkGroupSize.y;
  const uint lid = gl_LocalInvocationIndex;
  if (lid < 3u) tile_changed[lid] = 0u;
  barrier();
  bool hole = false;
  for (uint i = lid; i < kTile * kTile; i += threads) {
    ivec2 g;
    if (!image_pixel(uvec2(kHalo + i % kTile, kHalo + i / kTile), g)) continue;
    const int index = layer_base + g.y * int(push.width) + g.x;
    if (is_empty(texelFetch(source, index).x) && has_neighbour(direction_at(directions, index)))
      hole = true;
  }
  if (hole) atomicOr(tile_changed[0], 1u);
  barrier();
  if (tile_changed[0] == 0u) {  // the same in every invocation
    for (uint i = lid; i < kTile * kTile; i += threads) {
      ivec2 g;
      if (!image_pixel(uvec2(kHalo + i % kTile, kHalo + i / kTile), g)) continue;
      const int index = layer_base + g.y * int(push.width) + g.x;
      destination[index] = texelFetch(source, index).x;
    }
    return;
  }
  for (uint i = lid; i < kRegionPixels; i += threads) {
    const uvec2 r = uvec2(i % kRegion, i / kRegion);
    ivec2 g;
    const bool inside = image_pixel(r, g);
    tile_values[i] = inside ? texelFetch(source, layer_base + g.y * int(push.width) + g.x).x
                            : kEmptyValue;
  }
  barrier();
  uint current = 0u;
  for (uint p = 0u; p < push.passes; ++p) {
    const uint from = current * kRegionPixels, to = (1u - current) * kRegionPixels;
    if (lid == 0u) tile_changed[(p + 1u) % 3u] = 0u;
    bool changed = false;
    // Pixels whose 8 neighbours are still exact after p passes.
    const uint lo = p + 1u, hi = kRegion - 2u - p;
    bool filled_here = false;
    for (uint i = lid; i < kRegionPixels; i += threads) {
      const uvec2 r = uvec2(i % kRegion, i / kRegion);
      uint value = tile_values[from + i];
      ivec2 g;
      if (is_empty(value) && r.x >= lo && r.x <= hi && r.y >= lo && r.y <= hi &&
          image_pixel(r, g)) {
        const Direction d = direction_at(directions, layer_base + g.y * int(push.width) + g.x);
        uint neighbour[2] = uint[2](kEmptyValue, kEmptyValue);
        float weight[2] = float[2](0.0, 0.0);
        for (uint k = 0u; k < 2u; ++k) {
          if (inpaint_neighbour(d, k, uvec2(g), push.width, push.height, push.wrap_x) < 0) continue;
          const ivec2 o = kNeighbours[(d.codes >> (8u * k)) & 0xffu];
          const uint v = tile_values[from + uint(int(i) + o.y * int(kRegion) + o.x)];
          if (is_empty(v)) continue;
          neighbour[k] = v;
          weight[k] = k == 0u ? d.weight0 : d.weight1;
        }
        if (weight[0] + weight[1] > 0.0) {
          value = blend(neighbour[0], weight[0], neighbour[1], weight[1]);
          changed = true;
          filled_here = filled_here || in_tile(r);
        }
      }
      tile_values[to + i] = value;
    }
    if (filled_here) filled[push.pass + p] = 1u;
    if (changed && p > 0u) atomicOr(tile_changed[p % 3u], 1u);
    barrier();
    current = 1u - current;
    if (p > 0u && tile_changed[p % 3u] == 0u) break;  // read by all after the barrier: uniform
  }
  const uint result = current * kRegionPixels;
  for (uint i = lid; i < kRegionPixels; i += threads) {
    const uvec2 r = uvec2(i % kRegion, i / kRegion);
    ivec2 g;
    if (in_tile(r) && image_pixel(r, g)) {
      destination[layer_base + g.y * int(push.width) + g.x] = tile_values[result + i];
    }
  }
}
