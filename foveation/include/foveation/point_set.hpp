// The perceptual point set on the 2W x 2H canvas with the centre of interest
// at (W, H) (thesis 4.1).
//
// FoveaPattern::kPixelGrid (the default): inside the radius where the eye
// resolves every pixel (f_c >= f_d, eqs. 2-4) one point at every canvas pixel
// centre, its rays spread over that pixel's square as a full render spreads
// them; beyond it adaptive Poisson-disc points, at most one in any canvas pixel,
// so no region ever holds more points than pixels. The canvas is shifted by
// whole pixels (gaze_mapping.hpp), so grid points always sit on screen pixel
// centres.
//
// FoveaPattern::kThesisPoisson: Poisson-disc points everywhere (thesis Table 1).
//
// Every Poisson point i keeps r_i = p(x_i) (eq. 4), the radius of the disc its
// rays are cast through (thesis 4.2); pairs obey the display's DiscRule
// (docs/foveation.md). A grid point keeps r = a = sqrt(1/pi), the disc of one
// pixel's area.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec2.hpp>

#include "foveation/display_model.hpp"
#include "foveation/progress.hpp"

namespace foveart::foveation {

// Thesis 4.2: points up to 10 px outside the screen are sampled too.
inline constexpr float kVisibleMarginPx = 10.0f;

// What a point's rays sample.
enum class PointFootprint : std::uint8_t {
  kDisc = 0,   // uniformly inside the disc of radius_px around the point (thesis 4.2)
  kPixel = 1,  // uniformly over the screen pixel the point is the centre of
};

struct PointSet {
  int canvas_width_px = 0;
  int canvas_height_px = 0;
  std::vector<glm::vec2> position_px;  // canvas coordinates, Hilbert order
  std::vector<float> radius_px;        // disc radius of each point
  std::vector<PointFootprint> footprint;  // per point; empty: every point a disc
  // How far outside the screen a point is still traced: the thesis's 10 px for
  // its Poisson set; 0 for the pixel-grid pattern, whose frames then trace at
  // most one point per screen pixel.
  float visible_margin_px = kVisibleMarginPx;
  // DisplayModel::exact_fovea_radius_px around the centre of interest (the canvas's
  // centre): the grid points within it are the pixel-exact fovea.
  float exact_fovea_radius_px = 0.0f;
  // DisplayModel::view_distance_px: a point's eccentricity is atan(its distance from the
  // canvas centre / this).
  float view_distance_px = 0.0f;

  std::size_t size() const { return position_px.size(); }
  bool on_pixel_grid(std::size_t i) const { return !footprint.empty() && footprint[i] == PointFootprint::kPixel; }
  // The canvas centre: the centre of interest (the gaze), in canvas pixels.
  glm::vec2 centre_px() const { return {0.5f * float(canvas_width_px), 0.5f * float(canvas_height_px)}; }
  // Point i's offset from it.
  glm::vec2 from_centre_px(std::size_t i) const { return position_px[i] - centre_px(); }
  // Point i is of the pixel-exact fovea: always traced, with all its rays.
  bool in_exact_fovea(std::size_t i) const {
    if (!on_pixel_grid(i)) return false;
    const glm::vec2 d = from_centre_px(i);
    return d.x * d.x + d.y * d.y <= exact_fovea_radius_px * exact_fovea_radius_px;
  }
};

// The display's pattern: the pixel grid (if any) then variable-radius Bridson
// sampling seeded at its rim (or at the centre of interest); deterministic for
// (display, seed). Throws std::invalid_argument on a bad display.
PointSet generate_point_set(const DisplayModel& display, std::uint64_t seed,
                            const ProgressFn& progress = {});

// Position of integer pixel coordinates (16 bits each) along the Hilbert curve
// over the 65536 x 65536 grid (Hilbert 1891), by the quadrant-rotation
// recurrence. Consecutive positions are 4-neighbours, so every run of the
// order is compact on the screen: a packet of 16 points spans less of it than
// in Morton order (thesis 4.1), whose runs jump between quadrants.
std::uint32_t hilbert_index(std::uint32_t x, std::uint32_t y);

}  // namespace foveart::foveation
