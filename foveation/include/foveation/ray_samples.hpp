// Per-point ray sample positions (thesis 4.2): spp positions uniformly inside
// each visible point's disc, from a per-point fixed seed, so a static gaze gives
// identical frames; a pixel-grid point's spread over its screen pixel exactly
// as the full render spreads that pixel's (same positions for the same seed).
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec2.hpp>

#include "foveation/point_set.hpp"
#include "foveation/visible_points.hpp"

namespace foveart::foveation {

// Contiguous arrays ready for a FoveartRayBatch: sample s of visible point v sits
// at [v * spp + s]; point_index holds the point set index of its point.
struct RaySamples {
  int spp = 0;
  std::vector<glm::vec2> sample_px;
  std::vector<std::uint32_t> point_index;

  std::size_t size() const { return sample_px.size(); }
};

// Throws std::invalid_argument when spp < 1.
RaySamples generate_ray_samples(const PointSet& points, const VisiblePoints& visible, int spp,
                                std::uint64_t seed, int screen_width_px);

// The offsets alone: sample s of point `point_index` inside a unit disc, pure function.
glm::vec2 unit_disc_sample(std::uint64_t seed, std::uint32_t point_index, int s);

// Sample s of pixel `pixel_index` (y * W + x) in [0, 1)^2 of the pixel: the
// full render's jitter, and the pixel-grid fovea's. Pure function.
glm::vec2 pixel_jitter(std::uint64_t pixel_index, std::uint32_t sample, std::uint64_t seed);

// Sample s of the pixel-grid point at screen position centre_px (a pixel
// centre) on a screen screen_width_px wide.
inline glm::vec2 pixel_sample_px(glm::vec2 centre_px, int s, std::uint64_t seed, int screen_width_px) {
  const glm::vec2 corner{float(int(centre_px.x)), float(int(centre_px.y))};
  const std::uint64_t pixel = std::uint64_t(int(centre_px.y)) * std::uint64_t(screen_width_px) + std::uint64_t(int(centre_px.x));
  return corner + pixel_jitter(pixel, std::uint32_t(s), seed);
}

}  // namespace foveart::foveation
