// A view's tables as the table chunks hold them (gpu/table_pack.hpp), read
// in 32-bit words: gather.comp's taps and cache_pixels.comp's neighbours.
// The includer declares `chunks` (the chunk buffers) and `canvas_px` (push
// constants) first; a workgroup reads one chunk (one 8x8 canvas tile row).
#ifndef FOVEART_TABLE_TAPS_GLSL
#define FOVEART_TABLE_TAPS_GLSL

uint word(uint c, uint i) { return chunks[c].words[i]; }

uint byte_at(uint c, uint base, uint i) { return (word(c, base + (i >> 2)) >> ((i & 3u) * 8u)) & 0xFFu; }

// 24-bit point index at byte offset b (the host pads one word at the end).
uint point_at(uint c, uint base, uint b) {
  const uint shift = (b & 3u) * 8u;
  uint v = word(c, base + (b >> 2)) >> shift;
  if (shift > 8u) v |= word(c, base + (b >> 2) + 1u) << (32u - shift);
  return v & 0xFFFFFFu;
}

// Which block of its tile canvas pixel cp lies in (foveation/gather_layout.hpp),
// and the block's first palette entry.
struct Block {
  uint index;  // within the chunk
  uint local;  // within the tile (row-major blocks)
};

Block block_of(uint c, ivec2 tile, ivec2 cp) {
  const int tiles_x = (canvas_px.x + 7) / 8;
  const uint info = word(c, word(c, H_TILE_INFO) + uint((tile.y - int(word(c, H_FIRST_ROW))) * tiles_x + tile.x));
  const int bs = 8 >> (info >> 30);
  const int tw = min(8, canvas_px.x - tile.x * 8);
  const ivec2 l = cp - tile * 8;
  const uint local = uint((l.y / bs) * ((tw + bs - 1) / bs) + l.x / bs);
  return Block((info & 0x3FFFFFFFu) + local, local);
}

// The tile-order ordinal of canvas pixel cp of `tile` within chunk c
// (foveation/gather_layout.hpp): its taps sit at ordinal * k.
uint tile_ordinal(uint c, ivec2 tile, ivec2 cp) {
  const int tw = min(8, canvas_px.x - tile.x * 8), th = min(8, canvas_px.y - tile.y * 8);
  const ivec2 l = cp - tile * 8;
  return uint(tile.y * 8 * canvas_px.x + tile.x * 8 * th + l.y * tw + l.x) - word(c, H_ORDINAL_BASE);
}

#endif
