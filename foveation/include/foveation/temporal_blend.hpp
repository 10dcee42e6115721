// The temporal blend of one eye (temporal anti-aliasing, thesis 2.5 and 6.1): the history image is
// constrained to the current frame's 3x3 neighbourhood — min/max clamping
// (Karis 2014) or variance clipping towards the mean (Salvi 2016) — and then
// blended with the current frame. A gaze jump, a size change or the onset of a
// saccade or blink resets the history: that frame is the current frame alone.
// A saccade's later frames accumulate again (the eye is blind during it, and a
// restart in each of them would show the raw frame's noise every frame).
// With TemporalOptions::mean_while_young a young history is the plain mean of its
// frames: after a reset the k-th frame weighs 1 / k until that falls to
// current_weight (progressive accumulation, then the exponential blend), so a
// saccade's restart is averaged away while the eye is blind to it instead of
// lingering as (1 - alpha)^k of one raw frame.
//
// Not thread-safe: one instance per eye, called from one thread; accumulate()
// spreads its rows over the executor it is given.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec2.hpp>

#include "foveation/executor.hpp"
#include "foveation/image.hpp"
#include "foveation/history_reprojection.hpp"

namespace foveart::foveation {

enum class HistoryClip : std::uint8_t { minmax_clamp = 0, variance_clip = 1 };

struct TemporalOptions {
  // alpha of the exponential blend (Karis 2014) for a frame of one ray per
  // point; a frame of more rays blends with temporal_options_for_rays' weight.
  float current_weight = 0.1f;
  HistoryClip constraint = HistoryClip::variance_clip;
  float variance_gamma = 1.0f;   // box mu +- gamma sigma (Salvi 2016)
  // The box is at least mu +- clip_floor wide: history closer than that to a
  // flat box is kept. 1/4096 is below one 8-bit sRGB step anywhere (3.0e-4 at
  // black) and far above float rounding (1.2e-7 at 1), so the clip never
  // hinges on rounding: the CPU and GPU paths stay within one 8-bit step.
  float clip_floor = 1.0f / 4096.0f;
  float reset_distance_px = 40.0f;  // gaze moved further since the last frame -> reset
  HistorySampling history_sampling = HistorySampling::catmull_rom;  // reading a reprojected history
  // true: the k-th frame since a reset weighs max(1 / k, current_weight), the
  // mean of a young history (a variant the lab measures; the product's modes
  // leave it false): current_weight from the second frame on.
  bool mean_while_young = false;
};

// The weight of a frame blended into a history that already holds
// `frames_held` frames (0: a reset, weight 1): max(1 / (frames_held + 1),
// current_weight) with options.mean_while_young, else current_weight.
float temporal_frame_weight(const TemporalOptions& options, std::uint32_t frames_held);

// The options for frames of `rays_per_point` rays each: current_weight becomes
// that of n one-ray frames blended in turn, 1 - (1 - alpha)^n. The history then
// holds as many rays whatever a frame carries, and ages fewer frames when frames
// carry more: its resampling blur and lag grow with its age in frames, not in
// rays. A young history's mean needs no change: k frames of n rays each are
// k n rays, and n more weigh n / (k n + n) = 1 / (k + 1). n <= 1: the options
// unchanged.
TemporalOptions temporal_options_for_rays(TemporalOptions options, int rays_per_point);

class TemporalAccumulator {
 public:
  explicit TemporalAccumulator(const TemporalOptions& options = {}) : options_(options) {}

  // Blends `current` (rendered at `gaze_px`) into the history and returns the
  // output (valid until the next call). `saccade` is the gaze provider's
  // saccade-or-blink flag for this frame: its first frame (the frame after
  // detection) resets; while it stays set, the jump rule alone decides.
  const ImageRgb& accumulate(const ImageRgb& current, glm::vec2 gaze_px, Executor& executor, bool saccade = false);

  // The same with `warped_history` (the previous output reprojected into this
  // view: history_reprojection.hpp) as the history; pixels with valid[p] == 0 take
  // the current frame alone. Same reset rule.
  const ImageRgb& accumulate_reprojected(const ImageRgb& current, const ImageRgb& warped_history,
                                         const std::vector<std::uint8_t>& valid, glm::vec2 gaze_px,
                                         Executor& executor, bool saccade = false);
  // The last output (the history the next frame blends with).
  const ImageRgb& history() const { return history_; }

  // The reset rule of accumulate() alone, for a caller that blends elsewhere
  // (the layer's GPU path): records a width x height frame at gaze_px and
  // returns whether its history restarts. Keeps no image; frame_weight() is
  // then the weight to blend this frame with.
  bool begin_frame(int width_px, int height_px, glm::vec2 gaze_px, bool saccade = false);

  void reset() { valid_ = false; }
  bool last_was_reset() const { return last_reset_; }
  // The last frame's blend weight (1 on a reset): temporal_frame_weight() of the
  // frames the history held before it.
  float frame_weight() const { return frames_held_ <= 1 ? 1.0f : temporal_frame_weight(options_, frames_held_ - 1); }
  // Frames the history holds, the last one included (capped at 2^16).
  std::uint32_t frames_held() const { return frames_held_; }
  std::uint64_t reset_count() const { return resets_; }
  const TemporalOptions& options() const { return options_; }

 private:
  void blend(const ImageRgb& current, const ImageRgb& history, const std::uint8_t* valid, Executor& executor);
  void restart_history(const ImageRgb& current);

  TemporalOptions options_;
  ImageRgb history_;
  ImageRgb scratch_;
  glm::vec2 gaze_px_{};
  int width_px_ = 0;
  int height_px_ = 0;
  bool valid_ = false;
  bool last_reset_ = false;
  bool flagged_ = false;  // the last frame's saccade-or-blink flag
  std::uint32_t frames_held_ = 0;
  std::uint64_t resets_ = 0;
};

}  // namespace foveart::foveation
