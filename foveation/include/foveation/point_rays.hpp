// Stage 2 of the frame: each visible point's rays (thesis 4.2). A pixel-grid
// point casts its rays over its own pixel with the pixel filter, as the full
// render samples that pixel; any other point jittered in its disc.
#pragma once

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

class PointRays {
 public:
  // `points` must outlive this. jitter_each_frame: the seed changes every
  // frame, so disc offsets are made per frame rather than once.
  PointRays(const PointSet& points, int rays_per_point, PixelFilter pixel_filter, bool jitter_each_frame);

  // Before a frame of jitter seed `seed`: makes the disc offsets once for a
  // fixed seed (precomputed while they take at most 64 MB).
  void prepare(std::uint64_t seed, Executor& executor);

  // The rays of points ids (at region.to_screen of their positions) into batch
  // slots [0, ids.size() * rays_per_point()), point by point.
  void set_rays(RayBatch& batch, std::span<const std::uint32_t> ids, const VisibleRegion& region,
                int screen_width_px) const;

  std::uint32_t rays_per_point() const { return rays_per_point_; }

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
