// Stage 2 of the frame: each visible point's rays (thesis 4.2). A pixel-grid
// point casts its rays over its own pixel with the pixel filter, as the full
// render samples that pixel; any other point jittered in its disc.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/vec2.hpp>

#include "foveation/executor.hpp"
#include "foveation/eye_rays.hpp"
#include "foveation/point_set.hpp"
#include "foveation/ray_batch.hpp"
#include "foveation/ray_samples.hpp"

namespace foveart::foveation {

class PointRays {
 public:
  // `points` must outlive this. jitter_each_frame: the seed changes every
  // frame, so disc offsets are made per frame rather than once.
  PointRays(const PointSet& points, int rays_per_point, PixelFilter pixel_filter, bool jitter_each_frame);

  // Before a frame of jitter seed `seed`: makes the disc offsets once for a
  // fixed seed (precomputed while they take at most 64 MB).
  void prepare(std::uint64_t seed, Executor& executor);

  // Point `id`'s rays, at screen position screen_px, into batch slots
  // [first_slot, first_slot + rays_per_point()).
  void set_rays(RayBatch& batch, std::size_t first_slot, std::uint32_t id, glm::vec2 screen_px,
                const ScreenRayMap& rays, glm::vec3 origin_m, int screen_width_px) const {
    const std::uint32_t spp = rays_per_point_;
    const bool on_grid = points_.on_pixel_grid(id);
    for (std::uint32_t s = 0; s < spp; ++s) {  // one call site of set_ray, so that it is inlined
      const glm::vec2 sample_px =
          on_grid      ? pixel_sample_px(screen_px, int(s), seed_, screen_width_px, pixel_filter_)
          : precomputed_ ? screen_px + offset_px_[std::size_t(id) * spp + s]
                         : screen_px + unit_disc_sample(seed_, id, int(s)) * points_.radius_px[id];
      batch.set_ray(first_slot + s, rays, origin_m, sample_px, id);
    }
  }

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
