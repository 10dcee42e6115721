// Stage 2 of the frame: each visible point's rays (thesis 4.2). A pixel-grid
// point casts its rays over its own pixel with the pixel filter, as the full
// render samples that pixel; any other point jittered in its disc.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec2.hpp>

#include "foveation/executor.hpp"
#include "foveation/point_set.hpp"
#include "foveation/ray_batch.hpp"
#include "foveation/ray_samples.hpp"
#include "foveation/visible_points.hpp"

namespace foveart::foveation {

// Rays a Poisson point casts when they follow the content (ContentDensityOptions::
// rays_contrast > 0), of at most rays_per_point. Its disc: thesis 8.2, a point at
// pixel density needs fewer rays than one that stands for an area of pixels, so the
// share is the disc's area over that of a disc one pixel in radius, at most 1. The
// tile's contrast: the point's colour is a mean of n rays, its error sigma / sqrt(n)
// (Monte Carlo standard error) with sigma bounded by the tile's contrast, so holding
// the error of a tile at rays_contrast for lower contrasts takes (contrast /
// rays_contrast)^2 of the rays. At least one ray.
std::uint32_t point_ray_count(std::uint32_t rays_per_point, float radius_px, float tile_contrast, float rays_contrast);

// Steps of the contrast from which a point casts all its rays, by eccentricity
// (ContentDensityOptions::rays_doubling_ecc_deg): rays_contrast doubles at each step a
// point lies beyond. A step is a squared distance from the canvas centre (the gaze), so
// that both traces (device_rays.comp too) count a point's steps with the same float tests.
inline constexpr int kRaysContrastSteps = 4;
struct RaysContrastSteps {
  float rays_contrast = 0.0f;
  std::array<float, kRaysContrastSteps> distance_sq_px2{INFINITY, INFINITY, INFINITY, INFINITY};  // ascending

  // The contrast at dx, dy pixels from the canvas centre.
  float at(float dx_px, float dy_px) const {
    const float distance_sq_px2_of_point = dx_px * dx_px + dy_px * dy_px;
    float contrast = rays_contrast;
    for (const float step : distance_sq_px2)
      if (distance_sq_px2_of_point >= step) contrast *= 2.0f;
    return contrast;
  }
};
// Steps at 1..kRaysContrastSteps times doubling_ecc_deg, those under 90 degrees; none when
// doubling_ecc_deg is 0. view_distance_px: DisplayModel's D (eccentricity_deg).
RaysContrastSteps rays_contrast_steps(float rays_contrast, float doubling_ecc_deg, double view_distance_px);

inline constexpr int kMaxRaysPerPoint = 65535;  // TracedPoints::rays_cast holds a point's rays in 16 bits

class PointRays {
 public:
  // `points` must outlive this. jitter_each_frame: the seed changes every
  // frame, so disc offsets are made per frame rather than once. rays_per_point: 1 to kMaxRaysPerPoint.
  PointRays(const PointSet& points, int rays_per_point, PixelFilter pixel_filter, bool jitter_each_frame);

  // Before a frame of jitter seed `seed`: makes the disc offsets once for a
  // fixed seed (precomputed while they take at most 64 MB).
  void prepare(std::uint64_t seed, Executor& executor);

  // The rays of points ids (at region.to_screen of their positions) into batch
  // slots from 0, point by point: rays_per_point() each, or counts[j] (at most
  // rays_per_point(), the first of its rays) for ids[j] when counts is not empty.
  // Returns the rays set.
  std::uint32_t set_rays(RayBatch& batch, std::span<const std::uint32_t> ids, const VisibleRegion& region,
                         int screen_width_px, std::span<const std::uint32_t> counts = {}) const;

  std::uint32_t rays_per_point() const { return rays_per_point_; }
  // The rays point id casts in a tile of that contrast: point_ray_count at the point's step
  // of rays_contrast, or all of them for a point of the pixel-exact fovea (it samples its
  // pixel as the full render); a grid point beyond it (a denser scale's margin) casts as a
  // disc of one pixel's area.
  std::uint32_t rays_of(std::uint32_t id, float tile_contrast, const RaysContrastSteps& rays_contrast) const;

 private:
  const PointSet& points_;
  std::uint32_t rays_per_point_;
  PixelFilter pixel_filter_;
  bool jitter_each_frame_;
  std::uint64_t seed_ = 0;
  bool precomputed_ = false;
  std::vector<glm::vec2> offset_px_;  // per point and ray: its disc offset for seed_ (empty: none made yet)
};

}  // namespace foveart::foveation
