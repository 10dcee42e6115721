// Controls for temporal stability: what a history of the traced rays
// themselves reaches at one new ray per pixel per frame. Every ray traced since
// the last restart is kept in a render cache (foveation/ray_cache.hpp),
// anchored where it hit, and every frame filtered from where its anchor now
// projects into the pixels around it with the pixel filter's weights. What
// colour a kept ray brings is the choice (RayReuse):
//  - traced again from the current eye: today's colour, occlusion included,
//    so nothing a real history has to guess (reprojection, disocclusion,
//    shading that moved) is wrong. What it still flickers is set by how many
//    rays it holds and where they fall: the limit of any sample-reusing TAA
//    with the same restarts, at many rays a frame;
//  - the colour it was traced with, dropped once a nearer surface covers it:
//    the render cache at equal rays, whose stale shading and missed occlusion
//    show in its error.
#pragma once

#include <foveation/executor.hpp>
#include <foveation/image.hpp>
#include <foveation/ray_batch.hpp>
#include <foveation/ray_cache.hpp>
#include <foveation/ray_samples.hpp>
#include <foveation/ray_trace.h>

#include <cstdint>
#include <vector>

namespace foveart::eval {

// The colour a kept ray brings to a frame.
enum class RayReuse : std::uint8_t {
  retrace,      // traced again from the frame's eye through where its anchor projects
  keep_colour,  // the colour it was traced with; dropped when every new ray around it hits nearer
};

class SampleHistory {
 public:
  // seed: the new rays' jitter, frame i drawing with seed + i.
  SampleHistory(std::uint64_t seed, foveation::PixelFilter filter, RayReuse reuse = RayReuse::retrace)
      : seed_(seed), reuse_(reuse), cache_(foveation::RayCacheOptions{filter, reuse == RayReuse::keep_colour, 0}) {}

  // One frame: forgets every kept ray on a restart, adds one jittered ray per
  // pixel, traces the new rays (and with RayReuse::retrace every kept one)
  // through `fn` from `view` and filters them all into *out_linear. The
  // engine's failing status, or FOVEART_RESULT_SUCCESS.
  std::int32_t render(FoveartTraceRaysFn fn, void* user_data, const FoveartEyeView& view, std::uint64_t frame_index,
                      bool restart, foveation::Executor& executor, foveation::ImageRgb* out_linear);

  // Rays kept after the last render (its rays per frame).
  std::size_t rays() const { return cache_.size(); }

 private:
  std::uint64_t seed_;
  RayReuse reuse_;
  foveation::RayCache cache_;
  std::vector<foveation::RayBatch> batches_;  // per worker slot
};

}  // namespace foveart::eval
