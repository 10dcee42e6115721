#version 450
// The render cache's per-pixel data on the device, for a device-traced frame
// (foveation::RayHistory::prepare_pixels, the rule the CPU applies for the
// callback's rays): one workgroup per 8x8 canvas tile, as gather.comp.
//   A pixel a pixel-grid point drew a ray for: the pixel filter (footprint
//   1), covered beyond the farthest hit drawn for the 3x3 pixels around it
//   (foveation::farthest_around_3x3; one of them without a hit: cannot tell).
//   Any other: the disc footprint of its nearest point (disc_footprint_px),
//   covered beyond the farthest hit of its traced neighbours among the k
//   nearest (one without a finite hit, or none traced: cannot tell, -1).
#extension GL_GOOGLE_include_directive : require
#include "gpu/shader_interface/cache_pixels.h"

layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0, std430) readonly buffer Chunk { uint words[]; } chunks[FOVEART_MAX_TABLE_CHUNKS];
layout(set = 0, binding = 1, std430) readonly buffer Colors { vec4 colors[]; };  // per point; a = 1 traced
layout(set = 0, binding = 2, std430) readonly buffer Points { DevicePoint points[]; };
layout(set = 0, binding = 3, std430) readonly buffer PointFarthest { uint point_farthest[]; };
layout(set = 0, binding = 4, std430) readonly buffer Drawn { uint drawn[]; };
layout(set = 0, binding = 5, std430) writeonly buffer Pixels { vec2 pixels[]; };  // footprint, covering distance

#define H_FIRST_ROW FOVEART_CHUNK_FIRST_ROW
#define H_TILE_INFO FOVEART_CHUNK_TILE_INFO
#define H_BLOCK_PALETTE FOVEART_CHUNK_BLOCK_PALETTE
#define H_PALETTE FOVEART_CHUNK_PALETTE
#define H_SLOTS FOVEART_CHUNK_SLOTS
#define H_NEIGHBORS FOVEART_CHUNK_NEIGHBORS
#define H_ORDINAL_BASE FOVEART_CHUNK_ORDINAL_BASE
#define H_PIXEL_BASE FOVEART_CHUNK_PIXEL_BASE
#include "table_taps.glsl"

// The covering distance of a farthest-hit code (FOVEART_CACHE_FAR_UNKNOWN); < 0: cannot tell.
float covering_m(uint code) {
  return code == 0u || code == FOVEART_CACHE_FAR_UNKNOWN ? -1.0 : uintBitsToFloat(code - 1u);
}

// The 3x3 pixels around screen pixel sp: the farthest hit drawn there.
uint farthest_around(ivec2 sp) {
  uint farthest = 0u;
  for (int y = max(sp.y - 1, 0); y <= min(sp.y + 1, screen_px.y - 1); ++y)
    for (int x = max(sp.x - 1, 0); x <= min(sp.x + 1, screen_px.x - 1); ++x) {
      const uint d = drawn[y * screen_px.x + x];
      farthest = max(farthest, d == 0u ? FOVEART_CACHE_FAR_UNKNOWN : d);
    }
  return farthest;
}

// Canvas pixel cp's j-th nearest point: its j-th tap (weighted tables, taps
// in neighbour order) or its neighbour table's entry (NN).
uint neighbor(uint c, ivec2 tile, ivec2 cp, int j) {
  if (weighted == 0u) {
    const uint pixel = uint(cp.y * canvas_px.x + cp.x) - word(c, H_PIXEL_BASE);
    return point_at(c, word(c, H_NEIGHBORS), (pixel * uint(k) + uint(j)) * 3u);
  }
  const uint pal0 = word(c, word(c, H_BLOCK_PALETTE) + block_of(c, tile, cp).index);
  return word(c, word(c, H_PALETTE) + pal0 + byte_at(c, word(c, H_SLOTS), tile_ordinal(c, tile, cp) * uint(k) + uint(j)));
}

void main() {
  const ivec2 tile = first_tile + ivec2(gl_WorkGroupID.xy);
  const ivec2 cp = tile * 8 + ivec2(gl_LocalInvocationID.xy);
  const ivec2 sp = cp - canvas_offset_px;
  if (any(lessThan(sp, ivec2(0))) || any(greaterThanEqual(sp, screen_px))) return;
  uint c = 0u;  // the chunk holding this tile row: the same for the whole workgroup
  for (uint i = 1u; i < chunk_count; ++i)
    if (uint(tile.y) >= chunk_first_row[i / 4u][i % 4u]) c = i;
  const uint p = uint(sp.y * screen_px.x + sp.x);
  if (drawn[p] != 0u) {
    pixels[p] = vec2(1.0, covering_m(farthest_around(sp)));
    return;
  }
  // foveation::disc_footprint_px of the nearest point's radius, at least the pixel filter.
  const float radius_px = points[neighbor(c, tile, cp, 0)].position_radius_grid.z;
  const float footprint_px = filter_kind == FOVEART_RAY_CACHE_FILTER_BOX ? 1.7320508 * radius_px : radius_px;
  uint farthest = 0u;
  for (int j = 0; j < k; ++j) {
    const uint n = neighbor(c, tile, cp, j);
    if (colors[n].a != 0.0) farthest = max(farthest, point_farthest[n]);
  }
  pixels[p] = vec2(max(footprint_px, 1.0), covering_m(farthest));
}
