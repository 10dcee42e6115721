// Where the gaze puts the canvas on the screen (thesis 4.1-4.2, Fig. 10).
//
// Screen pixel p at gaze g reads canvas pixel p - g + (W, H). The gaze is rounded
// to whole pixels so canvas tables are read at integer offsets, and clamped to
// the screen [0, W] x [0, H] so every screen pixel maps inside the canvas.
#pragma once

#include <cstddef>

#include <glm/vec2.hpp>

namespace foveart::foveation {

struct GazeMapping {
  glm::vec2 gaze_px{};            // gaze actually used (clamped), screen pixels
  bool clamped = false;           // the requested gaze was off-screen
  int canvas_from_screen_x_px = 0;  // canvas = screen + offset
  int canvas_from_screen_y_px = 0;
  int screen_width_px = 0;
  int screen_height_px = 0;

  glm::vec2 screen_from_canvas(glm::vec2 canvas_px) const {
    return {canvas_px.x - float(canvas_from_screen_x_px), canvas_px.y - float(canvas_from_screen_y_px)};
  }
  // Screen pixel (x, y)'s canvas pixel, as a row-major index into a table canvas_width_px wide.
  std::size_t canvas_index(std::size_t x, std::size_t y, std::size_t canvas_width_px) const {
    return (y + std::size_t(canvas_from_screen_y_px)) * canvas_width_px + x + std::size_t(canvas_from_screen_x_px);
  }
};

// Throws std::invalid_argument for a NaN or infinite gaze or an empty screen.
GazeMapping map_gaze(int screen_width_px, int screen_height_px, glm::vec2 gaze_px);

}  // namespace foveart::foveation
