// Tile-local gather layout of an interpolation table, for a cache-friendly gather.
//
// The canvas is cut into 8x8 pixel tiles (smaller at the right and bottom
// edges). Each tile keeps a palette of the distinct point indices its pixels'
// k taps reference, ascending; a tap is then one byte, its slot in the
// palette. A tile whose taps reference more than 256 points is split into
// blocks of 4x4, 2x2 or 1x1 pixels (one palette each; 1x1 always fits k <= 256).
// A frame copies a block's palette colours into a small L1-resident array and
// gathers every tap from it, so the per-tap stream is 1 byte of index plus the
// weight instead of 3 bytes of global index plus a random 16-byte colour read.
//
// Pixels are stored in tile order (tile_ordinal): tiles row by row, pixels row
// by row inside a tile; weights and slots of pixel p sit at tile_ordinal(p) * k.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "foveation/executor.hpp"
#include "foveation/neighbor_table.hpp"

namespace foveart::foveation {

inline constexpr int kGatherTilePx = 8;

// Position of canvas pixel (x, y) in tile order on a width x height canvas.
inline std::size_t tile_ordinal(int width_px, int height_px, int x, int y) {
  const int ty = y / kGatherTilePx, tx = x / kGatherTilePx;
  const int th = std::min(kGatherTilePx, height_px - ty * kGatherTilePx);
  const int tw = std::min(kGatherTilePx, width_px - tx * kGatherTilePx);
  return std::size_t(ty) * kGatherTilePx * std::size_t(width_px) + std::size_t(tx) * kGatherTilePx * std::size_t(th) +
         std::size_t(y - ty * kGatherTilePx) * std::size_t(tw) + std::size_t(x - tx * kGatherTilePx);
}

struct GatherLayout {
  int width_px = 0;
  int height_px = 0;
  int k = 0;
  std::vector<std::uint8_t> tile_level;         // per tile: blocks of (8 >> level)^2 px
  std::vector<std::uint32_t> tile_first_block;  // per tile, plus the end
  std::vector<std::uint32_t> block_palette;     // per block, plus the end: offset into palette
  std::vector<std::uint32_t> palette;           // point indices, ascending within a block
  std::vector<std::uint8_t> slot;               // per tap, tile order: index into its block's palette

  int tiles_x() const { return (width_px + kGatherTilePx - 1) / kGatherTilePx; }
  int tiles_y() const { return (height_px + kGatherTilePx - 1) / kGatherTilePx; }
  bool empty() const { return slot.empty(); }
  std::size_t bytes() const {
    return tile_level.size() + tile_first_block.size() * 4 + block_palette.size() * 4 + palette.size() * 4 +
           slot.size();
  }
};

// The layout of the first k neighbours of every pixel of `neighbors`, built on
// the executor's threads. Throws std::invalid_argument for k outside 1..neighbors.k().
GatherLayout build_gather_layout(const NeighborTable& neighbors, int k, Executor& executor);

// Empty when `layout` is consistent for a width x height canvas with k taps and
// point_count points (sizes, offsets, palette sizes, every slot inside its
// palette, every palette entry below point_count); else what is wrong.
std::string gather_layout_error(const GatherLayout& layout, int width_px, int height_px, int k,
                                std::size_t point_count);

}  // namespace foveart::foveation
