// Points of the point set that fall on the screen at a gaze (thesis 4.2).
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec2.hpp>

#include "foveation/gaze_mapping.hpp"
#include "foveation/point_set.hpp"

namespace foveart::foveation {

// Thesis 4.2: points up to 10 px outside the screen are sampled too.
inline constexpr float kVisibleMarginPx = 10.0f;

struct VisiblePoints {
  std::vector<std::uint32_t> point_index;  // ascending (the point set's Morton order)
  std::vector<glm::vec2> screen_px;        // position of each on the screen

  std::size_t size() const { return point_index.size(); }
};

// Points whose screen position lies in [-margin, W + margin) x [-margin, H + margin).
VisiblePoints select_visible_points(const PointSet& points, const GazeMapping& mapping,
                                    float margin_px = kVisibleMarginPx);

// The same over the points [first, last) only, appended to *out (still
// ascending): concatenating consecutive ranges gives select_visible_points,
// so callers can split the scan over threads.
void select_visible_points_in(const PointSet& points, const GazeMapping& mapping, float margin_px,
                              std::size_t first, std::size_t last, VisiblePoints* out);

}  // namespace foveart::foveation
