// The full render with a foveated view's temporal history (docs/pricelist.md,
// "Fair baselines"): at a still view, frame i traces every pixel with the jitter
// seed a foveated view with these settings gives its frame i, and blends it
// into the history with the same TemporalAccumulator options, so that a
// full + TAA row of the price list accumulates exactly as a foveated + TAA row.
#pragma once

#include <foveation/executor.hpp>
#include <foveation/image.hpp>
#include <foveation/ray_trace.h>
#include <foveation/temporal_blend.hpp>
#include <foveation/view_settings.hpp>

#include <glm/vec2.hpp>

#include <cstdint>

namespace foveart::eval {

struct FullTaaFrame {
  std::int32_t status = FOVEART_RESULT_SUCCESS;  // the first failing callback status, if any
  double trace_ms = 0.0;                         // the full render's ray generation + tracing
  double temporal_ms = 0.0;                           // the blend into the history
};

class FullTaaRender {
 public:
  // `settings`: a foveated view's (render_view::taa_view_settings); its rays per point are the
  // full render's rays per pixel, and its seed, new-jitter rule, pixel filter and TAA
  // options are the full render's. Throws std::invalid_argument without an image history.
  explicit FullTaaRender(const foveation::ViewSettings& settings);

  // Frame `frame_index` of a still view and gaze; on a failing callback the history is kept as it was.
  FullTaaFrame render(FoveartTraceRaysFn trace_rays, void* user_data, const FoveartEyeView& view, glm::vec2 gaze_px,
                      std::uint64_t frame_index, foveation::Executor& executor);

  // The jitter seed of frame `frame_index`: FoveatedView's (sample_seed, + frame_index with new jitter each frame).
  std::uint64_t frame_seed(std::uint64_t frame_index) const;

  // The accumulated output of the last frame (empty before the first).
  const foveation::ImageRgb& image() const { return taa_.history(); }
  const foveation::TemporalAccumulator& accumulator() const { return taa_; }

 private:
  foveation::ViewSettings settings_;
  foveation::TemporalAccumulator taa_;
  foveation::ImageRgb frame_;  // the last full render, before the blend
};

}  // namespace foveart::eval
