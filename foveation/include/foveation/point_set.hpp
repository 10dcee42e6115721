// The perceptual point set: adaptive Poisson-disc points on the 2W x 2H canvas
// with the centre of interest at (W, H) (thesis 4.1).
//
// Every point i keeps r_i = p(x_i) (eq. 4), the radius of the disc its rays are
// cast through (thesis 4.2). Pairs obey the display's DiscRule: by default
// |x_i - x_j| >= max(r_i, r_j), which reproduces thesis Table 1; see
// docs/foveation.md for the choice.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec2.hpp>

#include "foveation/display_model.hpp"
#include "foveation/progress.hpp"

namespace foveart::foveation {

struct PointSet {
  int canvas_width_px = 0;
  int canvas_height_px = 0;
  std::vector<glm::vec2> position_px;  // canvas coordinates, Morton order
  std::vector<float> radius_px;        // disc radius of each point

  std::size_t size() const { return position_px.size(); }
};

// Variable-radius Bridson sampling on a grid, seeded at the centre of interest;
// deterministic for (display, seed). Throws std::invalid_argument on a bad display.
PointSet generate_point_set(const DisplayModel& display, std::uint64_t seed,
                            const ProgressFn& progress = {});

// 2D Morton (Z-order) code of integer pixel coordinates (16 bits each).
std::uint32_t morton_code(std::uint32_t x, std::uint32_t y);

}  // namespace foveart::foveation
