// Up to kHalo passes of directional inpainting (ALGORITHM.md §5 step 2) in one dispatch, exactly
// as that many ping-pong passes over the whole image: each workgroup loads its kTile x kTile
// pixels and a halo of kHalo around them into shared memory and runs the passes there. A pass
// reads only 8-neighbours, so after p passes the outer p rings of the loaded region are stale and
// the tile itself is exact after kHalo. One dispatch replaces kHalo, so the image is read and
// written once per kHalo passes instead of once per pass. A tile without holes skips the passes,
// and a pass that changes nothing in the region ends them (every later pass would repeat it). A
// tile without holes it could fill (empty pixels that have a direction) is copied through first,
// without its halo and without shared memory: most tiles are.
//
// Each dispatch also records per tile (tile_status, two sets used in turn: one read, the other
// written) whether it changed nothing, so that both buffers hold it, and whether it is final (no
// hole to fill: it stays so, holes only ever get filled). The next dispatch of the same run
// (push.pass > 0) skips a final tile, and a tile that, like its 8 neighbours (whose pixels form
// its halo), changed nothing: its region is what it was, so it would again change nothing.
// Skipping leaves the results bit for bit the same.
// The workgroup's z is the layer: plane z of the directions, source and destination.
//
// The including shader declares the texel buffers `directions` (inpaint.glsl) and `source`, the
// storage buffers Destination `destination`, Filled `filled` and Status `tile_status` (two uints
// per tile and layer) and the push constants (width, height, wrap_x, pass,
// passes, status_set), and defines, before including this file:
//   bool is_empty(uint value);
//   uint blend(uint v0, float w0, uint v1, float w1);  // a neighbour with w = 0 is absent
//   const uint kEmptyValue;

const uint kHalo = 8u;
layout(constant_id = 0) const uint kTile = 32u;  // chosen by the host to fit shared memory
const uint kRegion = kTile + 2u * kHalo;
const uint kRegionPixels = kRegion * kRegion;
// Region pixels per invocation (bits of a uint: at most 32, so 48^2 pixels need 72+ invocations).
const uint kPerInvocation =
    (kRegionPixels + gl_WorkGroupSize.x * gl_WorkGroupSize.y - 1u) / (gl_WorkGroupSize.x * gl_WorkGroupSize.y);

shared uint tile_values[2u * kRegionPixels];
// Whether pass p changed anything in the region, in slot p % 3 (three slots, so a slot is reset
// only when no invocation can still read or write it); slot 0 first says whether the tile has a
// hole to fill at all.
shared uint tile_changed[3];
shared uint tile_filled;  // whether any pass filled a pixel of the tile itself
shared uint tile_skip;    // whether the last dispatch left this tile as this one would

bool in_tile(uvec2 r) {
  return r.x >= kHalo && r.y >= kHalo && r.x < kHalo + kTile && r.y < kHalo + kTile;
}

// The image pixel under region pixel r (wrapped horizontally for panoramas); false outside.
bool image_pixel(uvec2 r, out ivec2 g) {
  g = ivec2(gl_WorkGroupID.xy * kTile) - int(kHalo) + ivec2(r);
  if (push.wrap_x != 0u) g.x = (g.x % int(push.width) + int(push.width)) % int(push.width);
  return g.x >= 0 && g.y >= 0 && g.x < int(push.width) && g.y < int(push.height);
}

// tile_status values.
const uint kTileChanged = 0u;    // a pixel of the tile was filled
const uint kTileUnchanged = 1u;  // nothing changed: both buffers hold the tile
const uint kTileFinal = 2u;      // no hole to fill, and both buffers hold the tile

uint tile_index(uvec2 t) {
  return (gl_WorkGroupID.z * gl_NumWorkGroups.y + t.y) * gl_NumWorkGroups.x + t.x;
}

// Whether the last dispatch left this tile as it would leave it again (see above).
bool can_skip(uint last) {
  const uint own = tile_status[last + tile_index(gl_WorkGroupID.xy)];
  if (own == kTileFinal) return true;
  if (own != kTileUnchanged) return false;
  const ivec2 grid = ivec2(gl_NumWorkGroups.xy);
  for (int dy = -1; dy <= 1; ++dy) {
    for (int dx = -1; dx <= 1; ++dx) {
      ivec2 t = ivec2(gl_WorkGroupID.xy) + ivec2(dx, dy);
      if (push.wrap_x != 0u) t.x = (t.x + grid.x) % grid.x;
      if (t.x < 0 || t.y < 0 || t.x >= grid.x || t.y >= grid.y) continue;
      if (tile_status[last + tile_index(uvec2(t))] == kTileChanged) return false;
    }
  }
  return true;
}

void inpaint_tile() {
  const int layer_base = int(gl_WorkGroupID.z * push.width * push.height);
  const uint threads = gl_WorkGroupSize.x * gl_WorkGroupSize.y;
  const uint lid = gl_LocalInvocationIndex;
  // The two status sets: consecutive dispatches of a run write them in turn (push.status_set),
  // each reading the one the dispatch before it wrote.
  const uint set_size = gl_NumWorkGroups.x * gl_NumWorkGroups.y * gl_NumWorkGroups.z;
  const uint now = push.status_set * set_size, last = set_size - now;
  const uint tile = tile_index(gl_WorkGroupID.xy);
  // The first dispatch of a run knows nothing of the other buffer.
  // One invocation decides (statuses read once, not by every lane), the others follow.
  if (lid == 0u) {
    const bool skip = push.pass > 0u && can_skip(last);
    if (skip) tile_status[now + tile] = tile_status[last + tile];
    tile_skip = skip ? 1u : 0u;
    tile_changed[0] = tile_changed[1] = tile_changed[2] = 0u;
    tile_filled = 0u;
  }
  barrier();
  if (tile_skip != 0u) return;  // the same in every invocation
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
    if (lid == 0u) tile_status[now + tile] = kTileFinal;
    return;
  }
  // Both halves of the region start as the image. Then each pass writes only what it must into
  // the half it writes (`to`, which holds the image two passes back): the pixels it fills and
  // those the pass before filled. Per invocation, bit m of `empty` and `fresh` says so of its
  // pixel lid + m * threads: empty and fillable, filled by the last pass.
  uint empty = 0u;
  for (uint m = 0u; m < kPerInvocation; ++m) {
    const uint i = lid + m * threads;
    if (i >= kRegionPixels) break;
    const uvec2 r = uvec2(i % kRegion, i / kRegion);
    ivec2 g;
    const bool inside = image_pixel(r, g);
    const int index = layer_base + g.y * int(push.width) + g.x;
    const uint value = inside ? texelFetch(source, index).x : kEmptyValue;
    tile_values[i] = value;
    tile_values[kRegionPixels + i] = value;
    if (inside && is_empty(value) && has_neighbour(direction_at(directions, index)))
      empty |= 1u << m;
  }
  barrier();
  uint current = 0u, fresh = 0u;
  for (uint p = 0u; p < push.passes; ++p) {
    const uint from = current * kRegionPixels, to = (1u - current) * kRegionPixels;
    if (lid == 0u) tile_changed[(p + 1u) % 3u] = 0u;
    bool changed = false;
    // Pixels whose 8 neighbours are still exact after p passes.
    const uint lo = p + 1u, hi = kRegion - 2u - p;
    bool filled_here = false;
    uint filled_now = 0u;
    for (uint m = 0u; m < kPerInvocation; ++m) {
      const uint bit = 1u << m, i = lid + m * threads;
      if ((fresh & bit) != 0u) tile_values[to + i] = tile_values[from + i];
      const uvec2 r = uvec2(i % kRegion, i / kRegion);
      ivec2 g;
      if ((empty & bit) == 0u || r.x < lo || r.x > hi || r.y < lo || r.y > hi || !image_pixel(r, g))
        continue;
      const Direction d = direction_at(directions, layer_base + g.y * int(push.width) + g.x);
      uint v0 = kEmptyValue, v1 = kEmptyValue;
      float w0 = 0.0, w1 = 0.0;
      if (inpaint_neighbour(d, 0u, uvec2(g), push.width, push.height, push.wrap_x) >= 0) {
        const ivec2 o = neighbour_offset(d.codes & 0xffu);
        v0 = tile_values[from + uint(int(i) + o.y * int(kRegion) + o.x)];
        if (!is_empty(v0)) w0 = d.weight0;
      }
      if (inpaint_neighbour(d, 1u, uvec2(g), push.width, push.height, push.wrap_x) >= 0) {
        const ivec2 o = neighbour_offset((d.codes >> 8u) & 0xffu);
        v1 = tile_values[from + uint(int(i) + o.y * int(kRegion) + o.x)];
        if (!is_empty(v1)) w1 = d.weight1;
      }
      if (w0 + w1 > 0.0) {
        tile_values[to + i] = blend(v0, w0, v1, w1);
        filled_now |= bit;
        changed = true;
        filled_here = filled_here || in_tile(r);
      }
    }
    empty &= ~filled_now;
    fresh = filled_now;
    if (filled_here) {
      filled[push.pass + p] = 1u;
      atomicOr(tile_filled, 1u);
    }
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
  if (lid == 0u) tile_status[now + tile] = tile_filled != 0u ? kTileChanged : kTileUnchanged;
}
