// Visible-point selection at a gaze (thesis 4.2: screen plus the point set's margin).
#include "foveation/visible_points.hpp"

#include <algorithm>

namespace foveart::foveation {

VisiblePoints select_visible_points(const PointSet& points, const GazeMapping& mapping,
                                    std::optional<float> margin_px) {
  VisiblePoints out;
  out.point_index.reserve(points.size() / 2);
  out.screen_px.reserve(points.size() / 2);
  const VisibleRegion region(mapping, margin_px.value_or(points.visible_margin_px));
  // A linear scan keeps the Hilbert order (stable, cache-friendly for the callback)
  // and costs ~1 ms for the FOVE set.
  for (std::size_t i = 0; i < points.size(); ++i) {
    const glm::vec2 s = region.to_screen(points.position_px[i]);
    if (region.contains(s)) {
      out.point_index.push_back(std::uint32_t(i));
      out.screen_px.push_back(s);
    }
  }
  return out;
}

std::vector<std::uint32_t> points_per_tile(const PointSet& points, const GazeMapping& mapping, std::uint32_t tile_w_px,
                                           std::uint32_t tile_h_px, std::uint32_t tiles_x, std::uint32_t tiles_y) {
  if (tile_w_px == 0 || tile_h_px == 0 || tiles_x == 0 || tiles_y == 0) return {};
  const VisibleRegion visible(mapping, points.visible_margin_px);  // the frame's own test
  const float w = float(mapping.screen_width_px), h = float(mapping.screen_height_px);
  std::vector<std::uint32_t> count(std::size_t(tiles_x) * tiles_y, 0);
  for (const glm::vec2& p : points.position_px) {
    const glm::vec2 screen = visible.to_screen(p);
    if (!visible.contains(screen)) continue;
    const std::uint32_t tx = std::min(tiles_x - 1, std::uint32_t(std::clamp(screen.x, 0.0f, w - 1.0f)) / tile_w_px);
    const std::uint32_t ty = std::min(tiles_y - 1, std::uint32_t(std::clamp(screen.y, 0.0f, h - 1.0f)) / tile_h_px);
    ++count[std::size_t(ty) * tiles_x + tx];
  }
  return count;
}

}  // namespace foveart::foveation
