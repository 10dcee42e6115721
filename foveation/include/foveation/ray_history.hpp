// Stage 5 of the frame with a ray history ("temporal": "rays"): every traced
// ray kept in a render cache (ray_cache.hpp) instead of an image, anchored
// where it hit and filtered, with this frame's rays, into the pixels around
// where it now lies: with the pixel filter over this frame's pixel grid,
// widened to the nearest point's disc beyond it (the Poisson periphery).
// The image history's restart rule (a saccade's or a blink's onset, a gaze
// jump) clears the cache, as does a failed frame.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "foveation/frame_stages.hpp"
#include "foveation/ray_cache.hpp"
#include "foveation/temporal_blend.hpp"
#include "foveation/view_tables.hpp"

namespace foveart::foveation {

struct RayHistoryOptions {
  PixelFilter pixel_filter = PixelFilter::box;
  std::uint32_t max_age_frames = 32;  // a kept ray is forgotten this many frames after it was traced (0: never)
  bool keep_through_restarts = false;  // an evaluation variant: a gaze jump or saccade keeps the rays
};

class RayHistory final : public TemporalHistory {
 public:
  // `tables` must outlive this; `blend` gives the restart rule (temporal_blend.hpp).
  RayHistory(const ViewTables& tables, const TemporalOptions& blend, const RayHistoryOptions& options);

  bool keeps_rays() const override { return true; }
  void forget() override;
  TemporalFrame decide(const FrameContext& frame, const TracedPoints& traced, Executor& executor) override;
  bool apply(const FrameContext& frame, const TracedPoints& traced, FrameResources& resources, Executor& executor,
             TemporalFrame* decision, std::string* error) override;
  std::size_t kept_rays() const override { return cache_.size(); }

 private:
  TemporalFrame begin(const FrameContext& frame);
  // pixel_ of this frame (with the pixel grid's depth test too when
  // `grid_depth_test`: a cache elsewhere, which runs the periphery's itself).
  void prepare_pixels(const FrameContext& frame, const TracedPoints& traced, bool grid_depth_test,
                      Executor& executor);
  // This frame's rays into the cache, and the cache's pixels into image_ (weight_ 0 where no ray reaches).
  void filter(const FrameContext& frame, const TracedPoints& traced, bool restart, Executor& executor);

  const ViewTables& tables_;
  RayHistoryOptions options_;
  TemporalAccumulator restarts_;  // the image history's restart rule only: it blends nothing
  RayCache cache_;
  std::optional<FoveartEyeView> last_view_;
  std::vector<std::uint8_t> grid_pixel_;  // per screen pixel: a pixel-grid point's this frame
  std::vector<glm::vec2> pixel_;          // per screen pixel: TemporalFrame::ray_pixels
  std::vector<float> drawn_farthest_m_, around_farthest_m_;  // the pixel grid's depth test, for a cache elsewhere
  std::vector<std::size_t> run_first_ray_;  // run r's rays start here among the frame's
  // This frame's pixels beyond its pixel grid, their filters' scale, and the cache's filter there.
  std::vector<std::uint32_t> periphery_pixels_;
  std::vector<glm::vec2> periphery_centre_px_;
  std::vector<float> periphery_footprint_px_, periphery_weight_;
  std::vector<glm::vec3> periphery_rgb_;
  ImageRgb image_;
  std::vector<float> weight_;
};

}  // namespace foveart::foveation
