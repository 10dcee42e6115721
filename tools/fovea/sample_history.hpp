// Controls for temporal stability: what a history of the traced rays
// themselves reaches at one new ray per pixel per frame. Every ray traced since
// the last restart is kept, anchored where it hit (a point on a surface, or a
// direction for a miss), and every frame filtered from where its anchor now
// projects into the pixels around it with the pixel filter's weights (a ratio
// estimator, pbrt-v4 8.8). What colour a kept ray brings is the choice
// (RayReuse):
//  - traced again from the current eye: today's colour, occlusion included,
//    so nothing a real history has to guess (reprojection, disocclusion,
//    shading that moved) is wrong. What it still flickers is set by how many
//    rays it holds and where they fall: the limit of any sample-reusing TAA
//    with the same restarts, at many rays a frame;
//  - the colour it was traced with, dropped once a nearer surface covers it:
//    a render cache (Walter et al. 1999) at equal rays, whose stale shading
//    and missed occlusion show in its error.
#pragma once

#include <foveation/executor.hpp>
#include <foveation/image.hpp>
#include <foveation/ray_batch.hpp>
#include <foveation/ray_samples.hpp>
#include <foveation/ray_trace.h>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <cstdint>
#include <vector>

namespace foveart::tools {

// The colour a kept ray brings to a frame.
enum class RayReuse : std::uint8_t {
  retrace,      // traced again from the frame's eye through where its anchor projects
  keep_colour,  // the colour it was traced with; dropped when every new ray around it hits nearer
};

// How much farther than the new rays around it a kept hit may lie and still
// count as seen (keep_colour): the new rays cross its pixels elsewhere, so a
// slanted surface's depth differs a little across them.
inline constexpr float kKeptRayOcclusionTolerance = 0.05f;

class SampleHistory {
 public:
  // seed: the new rays' jitter, frame i drawing with seed + i.
  SampleHistory(std::uint64_t seed, foveation::PixelFilter filter, RayReuse reuse = RayReuse::retrace)
      : seed_(seed), filter_(filter), reuse_(reuse) {}

  // One frame: forgets every kept ray on a restart, adds one jittered ray per
  // pixel, traces the new rays (and with RayReuse::retrace every kept one)
  // through `fn` from `view` and filters them all into *out_linear. The
  // engine's failing status, or FOVEART_RESULT_SUCCESS.
  std::int32_t render(FoveartTraceRaysFn fn, void* user_data, const FoveartEyeView& view, std::uint64_t frame_index,
                      bool restart, foveation::Executor& executor, foveation::ImageRgb* out_linear);

  // Rays kept after the last render (its rays per frame).
  std::size_t rays() const { return anchors_.size(); }

 private:
  struct Anchor {
    glm::vec3 point_m_or_direction{0.0f};
    bool at_infinity = false;  // a miss (or no depth): a direction, not a point
    glm::vec3 rgb{0.0f};       // as traced (RayReuse::keep_colour)
  };
  // keep_colour: drops the kept rays (those before `kept`) behind every new ray drawn within a pixel of theirs.
  void drop_covered_rays(std::size_t kept, const foveation::EyePose& pose, int width, int height,
                         foveation::Executor& executor);

  std::uint64_t seed_;
  foveation::PixelFilter filter_;
  RayReuse reuse_;
  std::vector<Anchor> anchors_;  // the kept rays, then (during render) this frame's new ones
  // Per ray of this frame (the kept ones, then one per pixel):
  std::vector<glm::vec2> sample_px_;     // where it falls now
  std::vector<std::uint8_t> on_screen_;  // within the filter's reach of the image
  std::vector<glm::vec3> rgb_;
  std::vector<float> new_depth_m_;           // per pixel: this frame's new ray's hit distance, +inf for a miss
  std::vector<std::uint32_t> by_row_;        // on-screen rays ordered by their pixel row
  std::vector<std::uint32_t> row_begin_;     // by_row_[row_begin_[y], row_begin_[y + 1]): row y's
  std::vector<foveation::RayBatch> batches_;  // per worker slot
};

// The pixel filter's weight of a ray `offset_px` from a pixel's centre, per
// axis: box 1 inside the pixel ([-0.5, 0.5)); bspline2 the quadratic B-spline (Unser 1999).
float pixel_filter_weight(foveation::PixelFilter filter, float offset_px);

}  // namespace foveart::tools
