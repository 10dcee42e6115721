// Measured density of a point set (docs/foveation.md, "The pixel-exact fovea").
#include "foveation/point_density.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace foveart::foveation {

PointDensity measure_point_density(const PointSet& points, double ring_width_px, double max_distance_px,
                                   int tile_px) {
  if (!(ring_width_px >= 1.0) || !(max_distance_px > 0.0) || tile_px < 1) {
    throw std::invalid_argument("measure_point_density: ring width and tile must be >= 1 px, the distance > 0");
  }
  PointDensity out;
  const int w = points.canvas_width_px, h = points.canvas_height_px;
  const double cx = 0.5 * double(w), cy = 0.5 * double(h);  // the centre of interest (W, H)
  const std::size_t ring_count = std::size_t(std::ceil(max_distance_px / ring_width_px));
  out.rings.resize(ring_count);
  for (std::size_t r = 0; r < ring_count; ++r) {
    out.rings[r].from_px = double(r) * ring_width_px;
    out.rings[r].to_px = double(r + 1) * ring_width_px;
  }
  auto ring_of = [&](double x, double y) { return std::size_t(std::hypot(x - cx, y - cy) / ring_width_px); };
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const std::size_t r = ring_of(double(x) + 0.5, double(y) + 0.5);
      if (r < ring_count) out.rings[r].area_px += 1.0;
    }
  }
  std::vector<std::uint8_t> per_pixel(std::size_t(w) * std::size_t(h), 0);
  const int tiles_x = (w + tile_px - 1) / tile_px, tiles_y = (h + tile_px - 1) / tile_px;
  std::vector<std::uint32_t> per_tile(std::size_t(tiles_x) * std::size_t(tiles_y), 0);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const glm::vec2 p = points.position_px[i];
    const int x = std::clamp(int(p.x), 0, w - 1), y = std::clamp(int(p.y), 0, h - 1);
    std::uint8_t& n = per_pixel[std::size_t(y) * std::size_t(w) + std::size_t(x)];
    n = std::uint8_t(std::min(255, n + 1));
    out.max_points_in_a_pixel = std::max<std::size_t>(out.max_points_in_a_pixel, n);
    ++per_tile[std::size_t(y / tile_px) * std::size_t(tiles_x) + std::size_t(x / tile_px)];
    if (const std::size_t r = ring_of(double(p.x), double(p.y)); r < ring_count) ++out.rings[r].points;
    out.pixel_grid_points += points.on_pixel_grid(i);
  }
  // Whole tiles only: an edge tile's few pixels would overstate a ratio.
  for (int ty = 0; ty < h / tile_px; ++ty)
    for (int tx = 0; tx < w / tile_px; ++tx)
      out.max_points_per_px = std::max(out.max_points_per_px, double(per_tile[std::size_t(ty) * std::size_t(tiles_x) + std::size_t(tx)]) /
                                                                  double(tile_px * tile_px));
  return out;
}

}  // namespace foveart::foveation
