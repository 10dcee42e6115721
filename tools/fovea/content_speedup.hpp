// What the scene content lets foveation gain (`fovea render --mode both`):
// full mode's measured cost of each screen tile, weighted by the foveated
// points traced in that tile.
#pragma once

#include <cstdint>
#include <span>

namespace foveart::fovea {

// A full frame's tiles: tiles_x columns of tile_w x tile_h pixels over a
// width x height image (the last row and column may be cut by the edge).
struct TileGrid {
  uint32_t width_px = 0;
  uint32_t height_px = 0;
  uint32_t tile_w_px = 0;
  uint32_t tile_h_px = 0;
  uint32_t tiles_x = 0;
};

// Σ tile_ms / Σ tile_ms × points / pixels of the tile: the speedup of a
// foveated frame that did nothing but trace its points, each costing what a
// full-frame pixel of its tile cost (tile_ms may be summed over frames).
// Equals pixels / points when every tile costs the same per pixel. 0 when the
// sizes disagree or no point falls in a tile with a cost.
double content_speedup(const TileGrid& grid, std::span<const double> tile_ms,
                       std::span<const uint32_t> points_per_tile);

}  // namespace foveart::fovea
