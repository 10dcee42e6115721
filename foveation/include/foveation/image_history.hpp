// Stage 5 of the frame with no history, or an image history (thesis 2.5, 6.1):
// the reconstruction blended into the last output (temporal_blend.hpp), which either
// restarts whenever the view moves or follows the head, reprojected by
// rotation and by the engine's depth (history_reprojection.hpp).
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "foveation/frame_stages.hpp"
#include "foveation/neighbor_table.hpp"
#include "foveation/temporal_blend.hpp"

namespace foveart::foveation {

// Every frame alone ("temporal": "off").
class NoHistory final : public TemporalHistory {
 public:
  explicit NoHistory(const TemporalOptions& blend) : blend_(blend) { blend_.current_weight = 1.0f; }
  void forget() override {}
  TemporalFrame decide(const FrameContext&, const TracedPoints&, Executor&) override;
  bool apply(const FrameContext& frame, const TracedPoints& traced, FrameResources& resources, Executor& executor,
             TemporalFrame* decision, std::string* error) override;

 private:
  TemporalOptions blend_;
};

class ImageHistory final : public TemporalHistory {
 public:
  // `neighbors` (a pixel's depth is its nearest traced point's) must outlive
  // this. reproject false: any new pose or frustum restarts the history.
  ImageHistory(const NeighborTable& neighbors, const TemporalOptions& blend, bool reproject);

  void forget() override;
  TemporalFrame decide(const FrameContext& frame, const TracedPoints& traced, Executor& executor) override;
  bool apply(const FrameContext& frame, const TracedPoints& traced, FrameResources& resources, Executor& executor,
             TemporalFrame* decision, std::string* error) override;

 private:
  bool moved(const FoveartEyeView& view) const;
  TemporalFrame decision_after(bool reset) const;
  void pixel_depths(const FrameContext& frame, const TracedPoints& traced, Executor& executor);

  const NeighborTable& neighbors_;
  bool reproject_;
  TemporalAccumulator accumulator_;
  std::optional<FoveartEyeView> last_view_;  // the history's view
  std::vector<float> depth_px_m_, history_depth_px_m_;  // per screen pixel, this and the last frame (empty: none)
  ImageRgb warped_;                                     // the history reprojected into this frame's view
  std::vector<std::uint8_t> warped_valid_;
};

}  // namespace foveart::foveation
