#include "content_speedup.hpp"

#include <algorithm>

namespace foveart::fovea {

double content_speedup(const TileGrid& g, std::span<const double> tile_ms, std::span<const uint32_t> points) {
  if (g.tile_w_px == 0 || g.tile_h_px == 0 || g.tiles_x == 0 || tile_ms.size() != points.size()) return 0.0;
  double cost_all = 0.0, cost_points = 0.0;
  for (size_t t = 0; t < tile_ms.size(); ++t) {
    const uint32_t x0 = static_cast<uint32_t>(t % g.tiles_x) * g.tile_w_px;
    const uint32_t y0 = static_cast<uint32_t>(t / g.tiles_x) * g.tile_h_px;
    if (x0 >= g.width_px || y0 >= g.height_px) return 0.0;  // a tile off the image: not this grid
    const double pixels = static_cast<double>(std::min(g.tile_w_px, g.width_px - x0)) *
                          static_cast<double>(std::min(g.tile_h_px, g.height_px - y0));
    cost_all += tile_ms[t];
    cost_points += tile_ms[t] * static_cast<double>(points[t]) / pixels;
  }
  return cost_points > 0.0 ? cost_all / cost_points : 0.0;
}

}  // namespace foveart::fovea
