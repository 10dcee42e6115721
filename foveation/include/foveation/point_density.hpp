// How densely a point set samples the canvas: the measured spacing curve
// (points per pixel by distance from the centre of interest) and the densest
// spots, the quantities behind "never more points than pixels" (thesis eq. 4's
// stated intent; docs/foveation.md, "The pixel-exact fovea").
#pragma once

#include <cstddef>
#include <vector>

#include "foveation/point_set.hpp"

namespace foveart::foveation {

struct DensityRing {
  double from_px = 0.0;  // distance from the centre of interest
  double to_px = 0.0;
  std::size_t points = 0;
  double area_px = 0.0;  // canvas pixels of the ring (exact annulus area clipped to the canvas, counted per pixel)
  double points_per_px() const { return area_px > 0.0 ? double(points) / area_px : 0.0; }
};

struct PointDensity {
  std::vector<DensityRing> rings;      // [0, ring_width), [ring_width, 2 ring_width), ...
  std::size_t max_points_in_a_pixel = 0;  // most points in any one canvas pixel
  double max_points_per_px = 0.0;      // densest aligned tile_px x tile_px block of the canvas
  std::size_t pixel_grid_points = 0;   // points with PointFootprint::kPixel
};

// Rings of ring_width_px out to max_distance_px, pixels counted by their
// centres; tiles of tile_px (8: the gather's tile) for the densest block.
// Throws std::invalid_argument for a width or tile below 1.
PointDensity measure_point_density(const PointSet& points, double ring_width_px, double max_distance_px,
                                   int tile_px = 8);

}  // namespace foveart::foveation
