// Visible-point selection at a gaze (thesis 4.2: screen plus the point set's margin).
#include "foveation/visible_points.hpp"

namespace foveart::foveation {

VisiblePoints select_visible_points(const PointSet& points, const GazeMapping& mapping,
                                    std::optional<float> margin_px) {
  VisiblePoints out;
  out.point_index.reserve(points.size() / 2);
  out.screen_px.reserve(points.size() / 2);
  const VisibleRegion region(mapping, margin_px.value_or(points.visible_margin_px));
  // A linear scan keeps the Morton order (stable, cache-friendly for the callback)
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

}  // namespace foveart::foveation
