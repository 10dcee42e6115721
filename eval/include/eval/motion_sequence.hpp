// Renders a scripted motion's frames (motion_views.hpp) for several tracks —
// the full render and foveated views of each temporal variant (off, an image
// history restarting on every pose change or reprojected, a render cache;
// temporal_variants.hpp) — and measures each against the
// converged reference sequence: a full render of every frame at the reference
// count, cached like the still reference (reference.hpp), frame i with seed +
// i so that the reference's errors are independent between frames. One
// implementation for `fovea-eval motion` and the price list's temporal
// columns. Frames are streamed: the reference of frame i, then every track's
// frame i, so nothing but the last frame is held.
#pragma once

#include <eval/motion_views.hpp>
#include <eval/reference.hpp>
#include <eval/temporal_metrics.hpp>

#include <engine/tracer.hpp>

#include <foveation/executor.hpp>
#include <foveation/foveated_view.hpp>

#include <nlohmann/json.hpp>

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace foveart::eval {

struct SequenceTrack {
  std::string id;
  std::string temporal;  // the foveated view's temporal variant (temporal_variant_name); empty for the full render
  bool full = false;
  int spp = 1;      // full render: rays per pixel, one jitter seed for every frame
  std::unique_ptr<foveation::FoveatedView> view;  // foveated
  // Measured:
  TemporalError error;
  std::vector<double> total_ms;  // per frame: select + trace + reconstruct + history, or the full render's trace
  engine::RayCounts rays;        // the first frame's
  std::uint32_t points = 0;      // the first frame's traced points (pixels for the full render)
  std::vector<std::uint32_t> points_by_frame;  // every frame's (content density thins them from the second)
  std::vector<std::uint64_t> primary_rays_by_frame;  // every frame's (rays by contrast vary them from the second)
  std::vector<int> temporal_reset_frames;  // the frames whose temporal history restarted
  std::uint64_t history_off_screen = 0, history_disoccluded = 0;  // pixels over the sequence (reproject)
};

struct SequenceReferenceOptions {
  std::string spp = "auto";  // "auto": the convergence check on the first frame picks the count for all
  int baseline_spp = 16;     // for the check (ReferenceOptions::baseline_spp)
  std::uint64_t seed = 1;    // frame i: seed + i
  // The pixel filter of the whole sequence: the reference's, the full render
  // tracks' and every foveated track's (run_sequence refuses a track with another).
  foveation::PixelFilter pixel_filter = foveation::PixelFilter::box;
  // The blend of a young history, the tracks' and the history-fed-the-reference control's
  // (TemporalOptions::mean_while_young; run_sequence refuses a track with another).
  bool mean_while_young = false;
  std::string cache_dir;     // empty: no cache
  // Measure the controls (SequenceRun::stable_blur, history_on_reference, sample_history, sample_history_kept,
  // ray_cache, ray_cache_kept)
  // beside the tracks; a caller that already has them from an earlier run of the same sequence skips them.
  bool controls = true;
};

struct SequenceRun {
  int reference_spp = 0;
  std::vector<int> tried_spp;      // the first frame's convergence check
  bool converged = true;
  int reference_frames_cached = 0;  // frames whose reference came from the cache
  double reference_ms = 0.0;        // this run's reference rendering
  ReferenceFloor floor;
  // The control: every reference frame through binomial_blur_3x3, a soft image
  // that is stable in the world by construction, measured like a track. What a
  // flicker measure charges it is what that measure charges softness alone.
  TemporalError stable_blur;
  // The history's ceiling: the layer's reprojected image history fed the converged reference
  // itself (no noise, history warped through the pixel-centre depth). What
  // it keeps of flicker and error is what the history's reprojection and
  // clip cost without any noise: the part that more averaging cannot remove.
  TemporalError history_on_reference;
  // What a history of the rays themselves reaches when nothing it keeps is
  // wrong (sample_history.hpp): one new jittered ray per pixel per frame,
  // every ray since the last restart kept and traced again from each frame's
  // eye where it first hit, filtered with the pixel filter. Restarting where
  // the layer's history restarts (the first frame, a saccade's or a blink's onset,
  // a gaze jump), and restarting on the first frame only: a history of traced
  // rays is anchored in the world, not on the gaze, so it need not forget
  // them at a saccade.
  TemporalError sample_history;
  TemporalError sample_history_kept;
  // The same histories at equal rays, a render cache: each kept ray brings
  // the colour it was traced with and is forgotten once a nearer surface
  // covers it (RayReuse::keep_colour); only the new ray per pixel is traced.
  TemporalError ray_cache;
  TemporalError ray_cache_kept;
  std::vector<MotionFrame> frames;
  // Per frame: the layer's image history has settled (settled_frames over the
  // motion's restarts: the first frame, a saccade's and a blink's frames).
  std::vector<std::uint8_t> settled;
};

// Frames after a restart before the layer's history counts as settled: its blend's
// time constant at one ray per point, 1 / TemporalOptions::current_weight (10
// frames, 143 ms at 70 fps; frames of more rays settle sooner, temporal_blend.hpp).
int history_settle_frames();

// The controls measured beside the tracks (SequenceRun), each under its JSON
// key prefix (<key>_flicker, <key>_flicker_tracked, <key>_flicker_csf, <key>_psnr in the
// reference's rings) and its label in reports: one list for the JSON, the
// price list's acceptance and report, and `fovea-eval motion`'s text.
struct SequenceControl {
  const char* key;
  const char* label;
  TemporalError SequenceRun::*error;
};
inline constexpr SequenceControl kSequenceControls[] = {
    {"stable_blur", "control: the reference blurred [1 2 1]^2, stable by construction", &SequenceRun::stable_blur},
    {"history_on_reference",
     "control: the layer's image history fed the reference (no noise: what its reprojection costs)",
     &SequenceRun::history_on_reference},
    {"sample_history",
     "control: every ray since the history's last restart, kept and traced again (a history without error)",
     &SequenceRun::sample_history},
    {"sample_history_kept", "control: every ray since the first frame, kept through saccades and blinks",
     &SequenceRun::sample_history_kept},
    {"ray_cache", "control: every ray since the history's last restart, its colour kept (a render cache at equal rays)",
     &SequenceRun::ray_cache},
    {"ray_cache_kept", "control: the render cache kept through saccades and blinks", &SequenceRun::ray_cache_kept},
};

struct SequenceHooks {
  ReferenceLog log;                                          // reference cache messages
  std::function<void(int frame, int frames)> frame_done;     // progress
  // Every track's frame in display values, e.g. to write it out; an error message stops the run.
  std::function<std::string(const SequenceTrack&, const MotionFrame&, const foveation::ImageRgb&)> image;
};

// Renders frames for every track against the reference sequence. false with
// *error when the engine fails, a frame fails or the cache cannot be written.
[[nodiscard]] bool run_sequence(engine::Tracer& tracer, std::uint64_t scene_hash,
                                const std::vector<MotionFrame>& frames, const SequenceReferenceOptions& reference,
                                std::vector<SequenceTrack>& tracks, foveation::Executor& executor,
                                const SequenceHooks& hooks, SequenceRun* run, std::string* error);

// {"spp", "spp_tried", "converged", "frames_from_cache", "render_ms", "rings": [{from_deg, to_deg,
// flicker_floor, flicker_tracked_floor, psnr_floor, <c>_flicker, <c>_flicker_tracked, <c>_psnr for the
// controls c = stable_blur, history_on_reference}], "settle_frames", "settled_frames" (how many),
// "<c>_bands": sequence_band_json of each control}: the reference sequence, its own contribution and the
// controls per ring.
nlohmann::ordered_json sequence_reference_json(const SequenceRun& run);
// {"id", "temporal", "spp", "frames", "ms" (median frame), "time_fraction" (of anchor_ms; null without),
// "points", "points_by_frame", "primary_rays_by_frame", "rays", "temporal_resets", "temporal_reset_frames",
// "history_off_screen", "history_disoccluded",
// "rings": [{from_deg, to_deg, flicker, flicker_tracked, psnr, rmse}], "bands": sequence_band_json}.
nlohmann::ordered_json sequence_track_json(const SequenceTrack& track, const SequenceRun& run, double anchor_ms);
// The central and the peripheral band (kCentralBand, kPeripheralBand) of one
// measured sequence: [{"band", "from_deg", "to_deg", "flicker_by_frame",
// "flicker_tracked_by_frame", "psnr_by_frame" (per frame; frame 0's flicker
// null), "settled": {"flicker", "flicker_tracked", "psnr"} over run.settled}]; [] when nothing was
// measured (no reference).
nlohmann::ordered_json sequence_band_json(const TemporalError& error, const SequenceRun& run);
// The entry for `band` in such an array (matched by name), or nullptr when
// `bands` is no array or lacks it (a run measured without a reference, or
// read back from an older results file).
const nlohmann::ordered_json* find_band(const nlohmann::ordered_json& bands, const RingBand& band);
double median_ms(std::vector<double> v);

}  // namespace foveart::eval
