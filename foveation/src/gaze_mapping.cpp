// Gaze → canvas offset (thesis 4.1, Fig. 10: the canvas shifts with the gaze).
#include "foveation/gaze_mapping.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace foveart::foveation {

GazeMapping map_gaze(int screen_width_px, int screen_height_px, glm::vec2 gaze_px) {
  if (screen_width_px <= 0 || screen_height_px <= 0) {
    throw std::invalid_argument("map_gaze: empty screen");
  }
  if (!std::isfinite(gaze_px.x) || !std::isfinite(gaze_px.y)) {
    std::ostringstream msg;
    msg << "gaze must be finite, got (" << gaze_px.x << ", " << gaze_px.y << ")";
    throw std::invalid_argument(msg.str());
  }
  GazeMapping m;
  m.screen_width_px = screen_width_px;
  m.screen_height_px = screen_height_px;
  const float w = float(screen_width_px);
  const float h = float(screen_height_px);
  m.gaze_px = {std::clamp(gaze_px.x, 0.0f, w), std::clamp(gaze_px.y, 0.0f, h)};
  m.clamped = m.gaze_px != gaze_px;
  // Canvas pixel = p - g + (W, H) with g rounded to whole pixels.
  m.canvas_from_screen_x_px = screen_width_px - int(std::lround(m.gaze_px.x));
  m.canvas_from_screen_y_px = screen_height_px - int(std::lround(m.gaze_px.y));
  return m;
}

}  // namespace foveart::foveation
