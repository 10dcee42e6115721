// Visible-point selection at a gaze (thesis 4.2: screen plus a 10 px margin).
#include "foveation/visible_points.hpp"

#include <algorithm>

namespace foveart::foveation {

VisiblePoints select_visible_points(const PointSet& points, const GazeMapping& mapping, float margin_px) {
  VisiblePoints out;
  out.point_index.reserve(points.size() / 2);
  out.screen_px.reserve(points.size() / 2);
  select_visible_points_in(points, mapping, margin_px, 0, points.size(), &out);
  return out;
}

void select_visible_points_in(const PointSet& points, const GazeMapping& mapping, float margin_px,
                              std::size_t first, std::size_t last, VisiblePoints* out) {
  const float x0 = -margin_px;
  const float y0 = -margin_px;
  const float x1 = float(mapping.screen_width_px) + margin_px;
  const float y1 = float(mapping.screen_height_px) + margin_px;
  const float dx = float(mapping.canvas_from_screen_x_px);
  const float dy = float(mapping.canvas_from_screen_y_px);
  // A linear scan keeps the Morton order (stable, cache-friendly for the callback)
  // and costs ~1 ms for the FOVE set.
  last = std::min(last, points.size());
  for (std::size_t i = first; i < last; ++i) {
    const glm::vec2 s{points.position_px[i].x - dx, points.position_px[i].y - dy};
    if (s.x >= x0 && s.x < x1 && s.y >= y0 && s.y < y1) {
      out->point_index.push_back(std::uint32_t(i));
      out->screen_px.push_back(s);
    }
  }
}

}  // namespace foveart::foveation
