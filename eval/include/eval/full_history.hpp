// The full render with a foveated view's temporal history (docs/lab/pricelist.md,
// "The fair baseline"): at a still view, frame i traces every pixel with the jitter
// seed a foveated view with these settings gives its frame i, and blends it
// into the history with the same TemporalAccumulator options, so that a
// full render with history in the price list accumulates exactly as a foveated one.
#pragma once

#include <foveation/executor.hpp>
#include <foveation/image.hpp>
#include <foveation/ray_trace.h>
#include <foveation/temporal_blend.hpp>
#include <foveation/view_settings.hpp>

#include <glm/vec2.hpp>

#include <cstdint>

namespace foveart::eval {

struct FullHistoryFrame {
  std::int32_t status = FOVEART_RESULT_SUCCESS;  // the first failing callback status, if any
  double trace_ms = 0.0;                         // the full render's ray generation + tracing
  double temporal_ms = 0.0;                           // the blend into the history
};

class FullHistoryRender {
 public:
  // `settings`: a foveated view's (variant_view_settings of TemporalVariant::image); its rays per
  // point are the full render's rays per pixel, and its seed, new-jitter rule, pixel filter and blend
  // options are the full render's. Throws std::invalid_argument without an image history.
  explicit FullHistoryRender(const foveation::ViewSettings& settings);

  // Frame `frame_index` of a still view and gaze; on a failing callback the history is kept as it was.
  FullHistoryFrame render(FoveartTraceRaysFn trace_rays, void* user_data, const FoveartEyeView& view, glm::vec2 gaze_px,
                      std::uint64_t frame_index, foveation::Executor& executor);

  // The jitter seed of frame `frame_index`: FoveatedView's (sample_seed, + frame_index with new jitter each frame).
  std::uint64_t frame_seed(std::uint64_t frame_index) const;

  // The accumulated output of the last frame (empty before the first).
  const foveation::ImageRgb& image() const { return history_.history(); }
  const foveation::TemporalAccumulator& accumulator() const { return history_; }

 private:
  foveation::ViewSettings settings_;
  foveation::TemporalAccumulator history_;
  foveation::ImageRgb frame_;  // the last full render, before the blend
};

}  // namespace foveart::eval
