#version 450
// Reconstruction of one eye (thesis 4.3): every screen pixel a k-tap weighted
// gather of point colours through the canvas tables, the GPU twin of
// foveation::gather. One workgroup is one 8x8 canvas tile; taps are read
// through the tile-local layout of foveation/gather_layout.hpp (per-block
// palettes of point indices, 1-byte taps, f16 or f32 weights) in 32-bit words,
// so no 8/16-bit storage feature is needed. NN reads the neighbour table.
//
// Invalid points never spread (docs/interpolation.md): a pixel with an
// untraced tap renormalises over its valid taps when their weight suffices
// (NN/MSM: any; RBF: half the weight sum), else takes the nearest valid
// neighbour, else the fallback colour. RBF results are clamped to the valid
// colours of the block (RbfClamp::block) or of the pixel's taps (::taps).
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "gpu/shader_interface/gather.h"
#include "table_taps.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

#define WEIGHTED FOVEART_GATHER_WEIGHTED
#define F16 FOVEART_GATHER_F16
#define CLAMP_TAPS FOVEART_GATHER_CLAMP_TAPS
#define CLAMP_BLOCK FOVEART_GATHER_CLAMP_BLOCK
#define RBF FOVEART_GATHER_RBF

float weight_at(uint c, uint base, uint i) {
  if ((flags & F16) == 0u) return uintBitsToFloat(word(c, base + i));
  const vec2 pair = unpackHalf2x16(word(c, base + (i >> 1)));
  return (i & 1u) == 0u ? pair.x : pair.y;
}

// NN: the nearest traced neighbour, else the fallback; depth: that point's.
vec3 nearest(uint c, ivec2 cp, out float depth) {
  const uint pixel = uint(cp.y * canvas_px.x + cp.x) - word(c, H_PIXEL_BASE);
  const uint base = word(c, H_NEIGHBORS);
  depth = DEPTH_UNKNOWN;
  for (int j = 0; j < neighbor_k; ++j) {
    const uint point = point_at(c, base, (pixel * uint(neighbor_k) + uint(j)) * 3u);
    const vec4 col = colors[point];
    if (col.a != 0.0) {
      depth = point_depth[point];
      return col.rgb;
    }
  }
  return fallback_rgb.rgb;
}

// RbfClamp::block: per block of the tile, the range of its valid palette
// colours, computed once per block by one invocation.
shared vec3 block_lo[64];
shared vec3 block_hi[64];

void block_ranges(uint c, ivec2 tile) {
  const int tiles_x = (canvas_px.x + 7) / 8;
  const uint info = word(c, word(c, H_TILE_INFO) + uint((tile.y - int(word(c, H_FIRST_ROW))) * tiles_x + tile.x));
  const int bs = 8 >> (info >> 30);
  const int tw = min(8, canvas_px.x - tile.x * 8), th = min(8, canvas_px.y - tile.y * 8);
  const uint blocks = uint(((tw + bs - 1) / bs) * ((th + bs - 1) / bs));
  const uint local = gl_LocalInvocationIndex;
  if (local < blocks) {
    const uint b = (info & 0x3FFFFFFFu) + local;
    const uint palette = word(c, H_PALETTE), bp = word(c, H_BLOCK_PALETTE);
    vec3 lo = vec3(1.0 / 0.0), hi = vec3(-1.0 / 0.0);
    for (uint i = word(c, bp + b); i < word(c, bp + b + 1u); ++i) {
      const vec4 col = colors[word(c, palette + i)];
      if (col.a != 0.0) lo = min(lo, col.rgb), hi = max(hi, col.rgb);
    }
    block_lo[local] = lo;
    block_hi[local] = hi;
  }
}

vec3 weighted(uint c, ivec2 tile, ivec2 cp, out float depth) {
  const Block block = block_of(c, tile, cp);
  const uint palette = word(c, H_PALETTE);
  const uint pal0 = word(c, word(c, H_BLOCK_PALETTE) + block.index);
  const uint ord = tile_ordinal(c, tile, cp);
  const uint slots = word(c, H_SLOTS), weights = word(c, H_WEIGHTS);

  vec3 acc = vec3(0.0), valid_acc = vec3(0.0);
  vec3 lo = vec3(1.0 / 0.0), hi = vec3(-1.0 / 0.0);
  float weight_sum = 0.0, valid_weight = 0.0;
  vec3 first_valid = fallback_rgb.rgb;
  depth = DEPTH_UNKNOWN;  // the nearest valid tap's point (taps are in neighbour order)
  bool any_valid = false, any_invalid = false;
  for (int j = 0; j < k; ++j) {
    const uint tap = ord * uint(k) + uint(j);
    const uint point = word(c, palette + pal0 + byte_at(c, slots, tap));
    const vec4 col = colors[point];
    const float w = weight_at(c, weights, tap);
    weight_sum += w;
    acc += w * col.rgb;
    if (col.a == 0.0) {
      any_invalid = true;
      continue;
    }
    valid_weight += w;
    valid_acc += w * col.rgb;
    lo = min(lo, col.rgb);
    hi = max(hi, col.rgb);
    if (!any_valid) {  // the nearest valid
      first_valid = col.rgb;
      depth = point_depth[point];
    }
    any_valid = true;
  }
  const bool clamp_taps = (flags & (CLAMP_TAPS | CLAMP_BLOCK)) != 0u;
  if (any_invalid) {
    const float min_fraction = (flags & RBF) != 0u ? 0.5 : 0.0;
    if (valid_weight > 0.0 && valid_weight >= min_fraction * weight_sum) {
      const vec3 v = valid_acc / valid_weight;
      return clamp_taps ? min(max(v, lo), hi) : v;
    }
    return first_valid;  // the fallback when no tap is valid
  }
  vec3 v = acc / weight_sum;  // the weights reproduce constants: renormalise by their stored sum
  if ((flags & CLAMP_TAPS) != 0u) v = min(max(v, lo), hi);
  if ((flags & CLAMP_BLOCK) != 0u) v = min(max(v, block_lo[block.local]), block_hi[block.local]);
  return v;
}

void main() {
  const ivec2 tile = first_tile + ivec2(gl_WorkGroupID.xy);
  const ivec2 cp = tile * 8 + ivec2(gl_LocalInvocationID.xy);
  const ivec2 sp = cp - canvas_offset_px;
  uint c = 0u;  // the chunk holding this tile row: the same for the whole workgroup
  for (uint i = 1u; i < chunk_count; ++i)
    if (uint(tile.y) >= chunk_first_row[i / 4u][i % 4u]) c = i;
  if ((flags & CLAMP_BLOCK) != 0u) {  // workgroup-uniform: every invocation reaches the barrier
    block_ranges(c, tile);
    barrier();
  }
  if (any(lessThan(sp, ivec2(0))) || any(greaterThanEqual(sp, screen_px))) return;
  float depth;
  const vec3 rgb = (flags & WEIGHTED) != 0u ? weighted(c, tile, cp, depth) : nearest(c, cp, depth);
  current[sp.y * screen_px.x + sp.x] = vec4(rgb, depth);
}
