// Points of the point set that fall on the screen at a gaze (thesis 4.2).
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include <glm/vec2.hpp>

#include "foveation/gaze_mapping.hpp"
#include "foveation/point_set.hpp"

namespace foveart::foveation {

// The visibility test on its own, for callers that fuse it into their own
// loop: a canvas point is visible when to_screen(p) lies in
// [-margin, W + margin) x [-margin, H + margin).
struct VisibleRegion {
  VisibleRegion(const GazeMapping& mapping, float margin_px)
      : offset_px(float(mapping.canvas_from_screen_x_px), float(mapping.canvas_from_screen_y_px)),
        x0(-margin_px),
        y0(-margin_px),
        x1(float(mapping.screen_width_px) + margin_px),
        y1(float(mapping.screen_height_px) + margin_px) {}
  glm::vec2 to_screen(glm::vec2 canvas_px) const { return canvas_px - offset_px; }
  bool contains(glm::vec2 screen_px) const {
    return screen_px.x >= x0 && screen_px.x < x1 && screen_px.y >= y0 && screen_px.y < y1;
  }

  glm::vec2 offset_px;  // canvas minus screen position
  float x0, y0, x1, y1;
};

struct VisiblePoints {
  std::vector<std::uint32_t> point_index;  // ascending (the point set's Hilbert order)
  std::vector<glm::vec2> screen_px;        // position of each on the screen

  std::size_t size() const { return point_index.size(); }
};

// Points whose screen position lies in [-margin, W + margin) x [-margin, H + margin),
// with the point set's own margin (PointSet::visible_margin_px) unless one is given.
VisiblePoints select_visible_points(const PointSet& points, const GazeMapping& mapping,
                                    std::optional<float> margin_px = std::nullopt);

// Points a frame at `mapping` traces per tile of a tiles_x x tiles_y grid of
// tile_w x tile_h screen tiles (row-major; points in the margin beyond the
// screen count in the nearest tile). Empty for an empty grid.
std::vector<std::uint32_t> points_per_tile(const PointSet& points, const GazeMapping& mapping, std::uint32_t tile_w_px,
                                           std::uint32_t tile_h_px, std::uint32_t tiles_x, std::uint32_t tiles_y);

}  // namespace foveart::foveation
