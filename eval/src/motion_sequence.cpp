// A motion's frames for several tracks against the reference sequence (motion_sequence.hpp).
#include <eval/motion_sequence.hpp>

#include <metrics/comparison_json.hpp>
#include <eval/sample_history.hpp>

#include <engine/render.hpp>

#include <metrics/image_metrics.hpp>
#include <foveation/temporal_blend.hpp>
#include <foveation/history_reprojection.hpp>
#include <foveation/temporal_mode.hpp>
#include <foveation/view_settings.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <utility>

namespace foveart::eval {
namespace {

using Json = nlohmann::ordered_json;

Json ring_bounds(std::size_t r) {
  return {{"from_deg", metrics::kRingEdgesDeg[r]},
          {"to_deg", metrics::number_or_null_json(metrics::kRingEdgesDeg[r + 1])}};
}

// One frame of a track, its display values into *display; "" or what failed.
std::string render_track_frame(engine::Tracer& tracer, const MotionFrame& f, SequenceTrack& t,
                               foveation::Executor& executor, std::uint64_t seed, foveation::PixelFilter pixel_filter,
                               foveation::ImageRgb* linear_full, foveation::ImageRgb* display) {
  const engine::RayCounts before = tracer.counts();
  const foveation::ImageRgb* image = nullptr;
  if (t.full) {
    engine::RenderSettings rs;
    rs.spp = t.spp;
    rs.seed = seed;  // one jitter for every frame, as the full render of the price list
    rs.pixel_filter = pixel_filter;
    const engine::RenderResult rr = engine::render_full(&foveart_engine_trace_rays, &tracer, f.view, rs, linear_full,
                                                        executor);
    if (rr.status != FOVEART_RESULT_SUCCESS)
      return t.id + ": engine callback failed with status " + std::to_string(rr.status);
    t.total_ms.push_back(rr.trace_ms);
    t.points_by_frame.push_back(std::uint32_t(f.view.width_px * f.view.height_px));
    image = linear_full;
  } else {
    foveation::FrameRequest request;
    request.view = f.view;
    request.gaze_px = f.gaze_px;
    request.frame_index = std::uint64_t(f.index);
    request.saccade = f.saccade;
    request.blink = f.blink;
    const foveation::FrameResult fr = t.view->render(request, &foveart_engine_trace_rays, &tracer, executor);
    if (!fr.ok()) return t.id + ": frame " + std::to_string(f.index) + ": " + fr.message;
    t.total_ms.push_back(fr.select_ms + fr.trace_ms + fr.reconstruct_ms + fr.temporal_ms);
    if (fr.temporal_reset) t.temporal_reset_frames.push_back(f.index);
    t.history_off_screen += fr.history_off_screen;
    t.history_disoccluded += fr.history_disoccluded;
    t.points_by_frame.push_back(fr.points);
    image = &t.view->image();
  }
  const engine::RayCounts frame_rays = tracer.counts() - before;
  t.primary_rays_by_frame.push_back(frame_rays.primary);
  if (f.index == 0) {
    t.rays = frame_rays;
    t.points = t.points_by_frame.front();
  }
  *display = metrics::display_encode(*image);
  return "";
}

// What the flicker along the motion needs (temporal_metrics.hpp): the scene's
// depth through every pixel centre of this frame and the one before.
struct Tracking {
  const MotionFrame* current = nullptr;
  const MotionFrame* previous = nullptr;  // null on the first frame
  std::vector<float> depth_m, previous_depth_m;
  foveation::ImageRgb warped_error;  // scratch
  std::vector<std::uint8_t> valid;   // scratch
};

// Adds a frame to `error` with its previous error warped along the motion
// (each pixel's surface where it was a frame before: history_reprojection.hpp).
void add_tracked_frame(TemporalError& error, const foveation::ImageRgb& display,
                       const foveation::ImageRgb& reference_display, const metrics::EccentricityMap& map,
                       Tracking& tracking, foveation::Executor& executor) {
  TrackedPrevious tracked;
  if (tracking.previous != nullptr) {
    foveation::reproject_history(error.previous_error(), tracking.previous_depth_m, tracking.previous->view,
                                 tracking.current->view, tracking.depth_m, tracking.warped_error, tracking.valid,
                                 executor);
    tracked = {&tracking.warped_error, &tracking.valid};
  }
  error.add_frame(display, reference_display, map, &tracked);
}

// The reference of one frame (the convergence check on the first with "auto"), its residual into the floor.
[[nodiscard]] bool reference_frame(engine::Tracer& tracer, std::uint64_t scene_hash, const MotionFrame& f,
                     const SequenceReferenceOptions& ref_options, const metrics::EccentricityMap& map,
                     foveation::Executor& executor, const ReferenceLog& log, SequenceRun* run,
                     foveation::ImageRgb* reference_linear, foveation::ImageRgb* reference_display,
                     std::string* error) {
  ReferenceOptions ro;
  const bool check = f.index == 0 && ref_options.spp == "auto";
  ro.spp = check ? 0 : (f.index == 0 ? std::stoi(ref_options.spp) : run->reference_spp);
  ro.baseline_spp = ref_options.baseline_spp;
  ro.seed = ref_options.seed + std::uint64_t(f.index);
  ro.pixel_filter = ref_options.pixel_filter;
  ro.cache_dir = ref_options.cache_dir;
  std::optional<Reference> ref = converged_reference(&foveart_engine_trace_rays, &tracer, scene_hash, f.view,
                                                     f.gaze_px, ro, executor, log, error);
  if (!ref) {
    *error = "reference of frame " + std::to_string(f.index) + ": " + *error;
    return false;
  }
  if (f.index == 0) {
    run->reference_spp = ref->spp;
    run->tried_spp = ref->tried_spp;
    run->converged = ref->converged;
  }
  if (ref->from_cache) ++run->reference_frames_cached;
  run->reference_ms += ref->render_ms;
  std::vector<float> residual(ref->half_difference2.size());
  for (std::size_t i = 0; i < residual.size(); ++i) residual[i] = ref->half_difference2[i] / 4.0f;
  run->floor.add_frame(residual, map, &ref->half_difference_luma);
  *reference_display = metrics::display_encode(ref->image);
  *reference_linear = std::move(ref->image);
  return true;
}

// The history's ceiling (SequenceRun::history_on_reference): the layer's image history, its history
// reprojected through the pixel-centre depth, fed the converged reference in
// place of a noisy frame; restarts at the same saccade and blink onsets.
struct HistoryOnReference {
  foveation::TemporalAccumulator blend;  // the layer's TemporalOptions, the tracks' young-history blend
  foveation::ImageRgb warped;          // scratch
  std::vector<std::uint8_t> valid;     // scratch
};

const foveation::ImageRgb& accumulate_reference(HistoryOnReference& c, const foveation::ImageRgb& reference_linear,
                                                const MotionFrame& f, const Tracking& tracking,
                                                foveation::Executor& executor) {
  const bool restart = f.saccade || f.blink;
  if (tracking.previous == nullptr) return c.blend.accumulate(reference_linear, f.gaze_px, executor, restart);
  foveation::reproject_history(c.blend.history(), tracking.previous_depth_m, tracking.previous->view, f.view,
                               tracking.depth_m, c.warped, c.valid, executor, c.blend.options().history_sampling);
  return c.blend.accumulate_reprojected(reference_linear, c.warped, c.valid, f.gaze_px, executor, restart);
}

// The sample-history controls (SequenceRun::sample_history, sample_history_kept, ray_cache, ray_cache_kept),
// each with its own jitter, apart from the reference's (seed + i) and the tracks'.
struct SampleHistories {
  SampleHistory at_restarts, kept, cache_at_restarts, cache_kept;
  foveation::ImageRgb image;  // scratch

  SampleHistories(std::uint64_t seed, foveation::PixelFilter filter)
      : at_restarts(seed + 0x9E3779B9ull, filter),
        kept(seed + 0x7F4A7C15ull, filter),
        cache_at_restarts(seed + 0x632BE59Bull, filter, RayReuse::keep_colour),
        cache_kept(seed + 0x85157AF5ull, filter, RayReuse::keep_colour) {}
};

// history_restarts: whether the layer's history restarted on this frame (TemporalAccumulator::last_was_reset
// of the history fed the reference, which sees the same gaze and flags): where `at_restarts` forgets its rays.
[[nodiscard]] bool add_sample_histories(SampleHistories& h, bool history_restarts, engine::Tracer& tracer,
                                        const MotionFrame& f, const foveation::ImageRgb& reference_display,
                                        const metrics::EccentricityMap& map, Tracking& tracking,
                                        foveation::Executor& executor, SequenceRun* run, std::string* error) {
  const struct {
    SampleHistory* history;
    TemporalError* measured;
    bool restart;
  } controls[] = {{&h.at_restarts, &run->sample_history, history_restarts},
                  {&h.kept, &run->sample_history_kept, f.index == 0},
                  {&h.cache_at_restarts, &run->ray_cache, history_restarts},
                  {&h.cache_kept, &run->ray_cache_kept, f.index == 0}};
  for (const auto& c : controls) {
    if (const std::int32_t st = c.history->render(&foveart_engine_trace_rays, &tracer, f.view,
                                                  std::uint64_t(f.index), c.restart, executor, &h.image);
        st != FOVEART_RESULT_SUCCESS) {
      *error = "sample history of frame " + std::to_string(f.index) + ": engine callback failed with status " +
               std::to_string(st);
      return false;
    }
    add_tracked_frame(*c.measured, metrics::display_encode(h.image), reference_display, map, tracking, executor);
  }
  return true;
}

}  // namespace

int history_settle_frames() {
  return int(std::ceil(1.0 / double(foveation::TemporalOptions{}.current_weight)));
}

double median_ms(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

bool run_sequence(engine::Tracer& tracer, std::uint64_t scene_hash, const std::vector<MotionFrame>& frames,
                  const SequenceReferenceOptions& ref_options, std::vector<SequenceTrack>& tracks,
                  foveation::Executor& executor, const SequenceHooks& hooks, SequenceRun* run, std::string* error) {
  for (const SequenceTrack& t : tracks) {
    if (t.view != nullptr && t.view->settings().pixel_filter != ref_options.pixel_filter) {
      *error = t.id + ": pixel filter " + foveation::pixel_filter_name(t.view->settings().pixel_filter) +
               ", the sequence's is " + foveation::pixel_filter_name(ref_options.pixel_filter) +
               " (its reference would not be the track's expectation)";
      return false;
    }
    if (t.view != nullptr && t.view->settings().temporal != foveation::TemporalMode::off &&
        t.view->settings().temporal_options.mean_while_young != ref_options.mean_while_young) {
      *error = t.id + ": its history's young-history blend differs from the sequence's (the control's)";
      return false;
    }
  }
  run->frames = frames;
  std::vector<std::uint8_t> restart(frames.size(), 0);
  for (std::size_t i = 0; i < frames.size(); ++i) restart[i] = frames[i].saccade || frames[i].blink ? 1 : 0;
  run->settled = settled_frames(restart, history_settle_frames());
  foveation::ImageRgb full_linear, display, reference_linear, reference_display, centre_image, blurred;
  Tracking tracking;
  foveation::TemporalOptions control_blend;
  control_blend.mean_while_young = ref_options.mean_while_young;
  HistoryOnReference history_on_reference{foveation::TemporalAccumulator(control_blend), {}, {}};
  SampleHistories sample_histories(ref_options.seed, ref_options.pixel_filter);
  const bool with_reference = !ref_options.spp.empty();
  for (const MotionFrame& f : frames) {
    const metrics::EccentricityMap map = metrics::eccentricity_map(f.view, f.gaze_px);
    if (with_reference && !reference_frame(tracer, scene_hash, f, ref_options, map, executor, hooks.log, run,
                                           &reference_linear, &reference_display, error))
      return false;
    tracking.current = &f;
    if (with_reference) {
      // The scene's depth through every pixel centre: where each pixel's surface was a frame
      // before, for the flicker along the motion (temporal_metrics.hpp).
      std::swap(tracking.previous_depth_m, tracking.depth_m);
      engine::RenderSettings rs;
      rs.jitter = false;
      rs.out_depth_m = &tracking.depth_m;
      if (const engine::RenderResult rr =
              engine::render_full(&foveart_engine_trace_rays, &tracer, f.view, rs, &centre_image, executor);
          rr.status != FOVEART_RESULT_SUCCESS) {
        *error = "depth of frame " + std::to_string(f.index) + ": engine callback failed with status " +
                 std::to_string(rr.status);
        return false;
      }
    }
    if (with_reference && ref_options.controls) {
      binomial_blur_3x3(reference_display, &blurred);
      add_tracked_frame(run->stable_blur, blurred, reference_display, map, tracking, executor);
      add_tracked_frame(run->history_on_reference,
                        metrics::display_encode(
                            accumulate_reference(history_on_reference, reference_linear, f, tracking, executor)),
                        reference_display, map, tracking, executor);
      if (!add_sample_histories(sample_histories, history_on_reference.blend.last_was_reset(), tracer, f,
                                reference_display, map, tracking, executor, run, error))
        return false;
    }
    for (SequenceTrack& t : tracks) {
      if (std::string e = render_track_frame(tracer, f, t, executor, ref_options.seed, ref_options.pixel_filter, &full_linear, &display);
          !e.empty()) {
        *error = e;
        return false;
      }
      if (with_reference) add_tracked_frame(t.error, display, reference_display, map, tracking, executor);
      if (hooks.image) {
        if (std::string e = hooks.image(t, f, display); !e.empty()) {
          *error = e;
          return false;
        }
      }
    }
    if (hooks.frame_done) hooks.frame_done(f.index + 1, int(frames.size()));
    tracking.previous = &f;
  }
  return true;
}

Json sequence_reference_json(const SequenceRun& run) {
  Json rings = Json::array();
  const TemporalRings floor = run.floor.rings();
  std::vector<TemporalRings> controls;
  for (const SequenceControl& c : kSequenceControls) controls.push_back((run.*c.error).rings());
  for (std::size_t r = 0; r < floor.size(); ++r) {
    Json j = ring_bounds(r);
    j["flicker_floor"] = metrics::number_or_null_json(floor[r].flicker_rms);
    j["flicker_tracked_floor"] = metrics::number_or_null_json(floor[r].flicker_tracked_rms);
    j["flicker_csf_floor"] = metrics::number_or_null_json(floor[r].flicker_csf_rms);
    j["psnr_floor"] = metrics::number_or_null_json(floor[r].psnr_db());
    for (std::size_t c = 0; c < controls.size(); ++c) {
      const std::string key = kSequenceControls[c].key;
      j[key + "_flicker"] = metrics::number_or_null_json(controls[c][r].flicker_rms);
      j[key + "_flicker_tracked"] = metrics::number_or_null_json(controls[c][r].flicker_tracked_rms);
      j[key + "_flicker_csf"] = metrics::number_or_null_json(controls[c][r].flicker_csf_rms);
      j[key + "_psnr"] = metrics::number_or_null_json(controls[c][r].psnr_db());
    }
    rings.push_back(j);
  }
  Json j = {{"spp", run.reference_spp}, {"spp_tried", run.tried_spp}, {"converged", run.converged},
            {"frames_from_cache", run.reference_frames_cached}, {"render_ms", run.reference_ms},
            {"seeds", "seed + frame index"}, {"rings", rings}, {"settle_frames", history_settle_frames()},
            {"settled_frames", std::count(run.settled.begin(), run.settled.end(), std::uint8_t(1))}};
  for (const SequenceControl& c : kSequenceControls)
    j[std::string(c.key) + "_bands"] = sequence_band_json(run.*c.error, run);
  return j;
}

Json sequence_band_json(const TemporalError& error, const SequenceRun& run) {
  Json bands = Json::array();
  if (error.frames() == 0) return bands;  // measured without a reference
  for (const RingBand& band : {kCentralBand, kPeripheralBand}) {
    Json flicker = Json::array(), tracked = Json::array(), psnr = Json::array();
    for (const TemporalRing& f : error.by_frame(band)) {
      flicker.push_back(metrics::number_or_null_json(f.flicker_rms));
      tracked.push_back(metrics::number_or_null_json(f.flicker_tracked_rms));
      psnr.push_back(metrics::number_or_null_json(f.psnr_db()));
    }
    const TemporalRing settled = error.pooled(band, &run.settled);
    bands.push_back({{"band", band.name}, {"from_deg", metrics::kRingEdgesDeg[band.begin]},
                     {"to_deg", metrics::number_or_null_json(metrics::kRingEdgesDeg[band.end])},
                     {"flicker_by_frame", flicker}, {"flicker_tracked_by_frame", tracked}, {"psnr_by_frame", psnr},
                     {"settled", {{"flicker", metrics::number_or_null_json(settled.flicker_rms)},
                                  {"flicker_tracked", metrics::number_or_null_json(settled.flicker_tracked_rms)},
                                  {"flicker_csf", metrics::number_or_null_json(settled.flicker_csf_rms)},
                                  {"psnr", metrics::number_or_null_json(settled.psnr_db())}}}});
  }
  return bands;
}

const Json* find_band(const Json& bands, const RingBand& band) {
  if (!bands.is_array()) return nullptr;
  for (const Json& b : bands)
    if (b.is_object() && b.value("band", std::string()) == band.name) return &b;
  return nullptr;
}

Json sequence_track_json(const SequenceTrack& t, const SequenceRun& run, double anchor_ms) {
  const double ms = median_ms(t.total_ms);
  Json rays = {{"primary", t.rays.primary}, {"shadow", t.rays.shadow}, {"reflection", t.rays.reflection},
               {"refraction", t.rays.refraction}, {"total", t.rays.total()}};
  Json j = {{"id", t.id},
            {"kind", t.full ? "full" : "foveated"},
            {"temporal", t.full ? Json(nullptr) : Json(t.temporal)},
            {"spp", t.spp},
            {"frames", t.error.frames()},
            {"ms", ms},
            {"frames_total_ms", t.total_ms},
            {"time_fraction", anchor_ms > 0.0 ? Json(ms / anchor_ms) : Json(nullptr)},
            {"points", t.points},
            {"points_by_frame", t.points_by_frame},
            {"primary_rays_by_frame", t.primary_rays_by_frame},
            {"rays", rays},
            {"temporal_resets", t.temporal_reset_frames.size()},
            {"temporal_reset_frames", t.temporal_reset_frames},
            {"history_off_screen", t.history_off_screen},
            {"history_disoccluded", t.history_disoccluded}};
  Json rings = Json::array();
  const TemporalRings m = t.error.rings();
  for (std::size_t r = 0; r < m.size(); ++r) {
    Json ring = ring_bounds(r);
    ring["flicker"] = metrics::number_or_null_json(m[r].flicker_rms);
    ring["flicker_tracked"] = metrics::number_or_null_json(m[r].flicker_tracked_rms);
    ring["flicker_csf"] = metrics::number_or_null_json(m[r].flicker_csf_rms);
    ring["psnr"] = metrics::number_or_null_json(m[r].psnr_db());
    ring["rmse"] = metrics::number_or_null_json(std::sqrt(m[r].error_mse));
    rings.push_back(ring);
  }
  j["rings"] = rings;
  j["bands"] = sequence_band_json(t.error, run);
  return j;
}

}  // namespace foveart::eval
