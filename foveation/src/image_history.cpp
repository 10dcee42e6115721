#include "foveation/image_history.hpp"

#include <cmath>
#include <cstring>

#include "foveation/history_reprojection.hpp"

namespace foveart::foveation {
namespace {

bool same_view(const FoveartEyeView& a, const FoveartEyeView& b) { return std::memcmp(&a, &b, sizeof a) == 0; }

}  // namespace

TemporalFrame NoHistory::decide(const FrameContext&, const TracedPoints&, Executor&) {
  TemporalFrame t;
  t.blend = blend_;
  return t;
}

bool NoHistory::apply(const FrameContext& frame, const TracedPoints& traced, FrameResources& resources,
                      Executor& executor, TemporalFrame* decision, std::string* error) {
  HostFrame* host = host_frame(resources, "the CPU's temporal history", error);
  if (host == nullptr) return false;
  *decision = decide(frame, traced, executor);
  host->output = &host->reconstructed;
  return true;
}

ImageHistory::ImageHistory(const NeighborTable& neighbors, const TemporalOptions& blend, bool reproject)
    : neighbors_(neighbors), reproject_(reproject), accumulator_(blend) {}

void ImageHistory::forget() {
  accumulator_.reset();
  last_view_.reset();
}

bool ImageHistory::moved(const FoveartEyeView& view) const { return !last_view_ || !same_view(*last_view_, view); }

TemporalFrame ImageHistory::decision_after(bool reset) const {
  TemporalFrame t;
  t.kept = true;
  t.reset = reset;
  t.blend = accumulator_.options();
  t.blend.current_weight = accumulator_.frame_weight();  // this frame's: one weight rule for both paths
  return t;
}

TemporalFrame ImageHistory::decide(const FrameContext& frame, const TracedPoints&, Executor&) {
  const bool view_moved = moved(frame.view);
  if (!reproject_ && view_moved) accumulator_.reset();
  const GazeMapping& m = frame.mapping;
  TemporalFrame t = decision_after(accumulator_.begin_frame(m.screen_width_px, m.screen_height_px, m.gaze_px, frame.restart));
  if (!t.reset && view_moved) t.history_view = last_view_;  // the caller reprojects from there
  last_view_ = frame.view;
  return t;
}

bool ImageHistory::apply(const FrameContext& frame, const TracedPoints& traced, FrameResources& resources,
                         Executor& executor, TemporalFrame* decision, std::string* error) {
  HostFrame* host = host_frame(resources, "the CPU's temporal history", error);
  if (host == nullptr) return false;
  const ImageRgb& reconstructed = host->reconstructed;
  const bool view_moved = moved(frame.view);
  const glm::vec2 gaze_px = frame.mapping.gaze_px;
  const ImageRgb* out = nullptr;
  ReprojectionStats reprojected;
  if (!reproject_) {
    if (view_moved) accumulator_.reset();
    out = &accumulator_.accumulate(reconstructed, gaze_px, executor, frame.restart);
  } else {
    // The history follows the head: reprojected into this view, by depth where the engine gave one.
    if (traced.any_depth) {
      pixel_depths(frame, traced, executor);
    } else {
      depth_px_m_.clear();
    }
    if (last_view_ && view_moved && accumulator_.history().width_px > 0) {
      reprojected = reproject_history(accumulator_.history(), history_depth_px_m_, *last_view_, frame.view, depth_px_m_,
                                      warped_, warped_valid_, executor, accumulator_.options().history_sampling);
      out = &accumulator_.accumulate_reprojected(reconstructed, warped_, warped_valid_, gaze_px, executor, frame.restart);
    } else {
      out = &accumulator_.accumulate(reconstructed, gaze_px, executor, frame.restart);
    }
    std::swap(history_depth_px_m_, depth_px_m_);
  }
  *decision = decision_after(accumulator_.last_was_reset());
  decision->history_off_screen = reprojected.off_screen;
  decision->history_disoccluded = reprojected.disoccluded;
  decision->history_with_depth = reprojected.with_depth;
  last_view_ = frame.view;
  host->output = out;
  return true;
}

void ImageHistory::pixel_depths(const FrameContext& frame, const TracedPoints& traced, Executor& executor) {
  // A pixel's depth is its nearest traced point's (neighbour order); NaN when none is in reach.
  const NeighborTable& nt = neighbors_;
  const GazeMapping& mapping = frame.mapping;
  const int w = mapping.screen_width_px, h = mapping.screen_height_px;
  depth_px_m_.resize(std::size_t(w) * std::size_t(h));
  executor.parallel_chunks(std::size_t(h), 16, [&](std::size_t y0, std::size_t y1, unsigned) {
    for (std::size_t y = y0; y < y1; ++y) {
      const std::size_t row = mapping.canvas_index(0, y, std::size_t(nt.width_px()));
      for (std::size_t x = 0; x < std::size_t(w); ++x) {
        const std::uint32_t p = nearest_valid_point(nt, row + x, traced.colors.rgba.data());
        depth_px_m_[y * std::size_t(w) + x] = p == kNoValidPoint ? NAN : traced.depth_m[p];
      }
    }
  });
}

}  // namespace foveart::foveation
