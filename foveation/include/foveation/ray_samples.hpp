// Per-point ray sample positions (thesis 4.2): spp positions uniformly inside
// each visible point's disc, from a per-point fixed seed, so a static gaze gives
// identical frames.
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
                                std::uint64_t seed);

// The offsets alone: sample s of point `point_index` inside a unit disc, pure function.
glm::vec2 unit_disc_sample(std::uint64_t seed, std::uint32_t point_index, int s);

}  // namespace foveart::foveation
