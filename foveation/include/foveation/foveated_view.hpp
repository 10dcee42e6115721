// The one foveated frame (thesis 4.2-4.3; docs/design.md "One frame in
// stages"), used by the OpenXR layer, `fovea render` and `fovea reconstruct`
// alike: a stage set of frame_stages.hpp, chosen once, run in order for one
// view. The CPU's set (make_cpu_stages): the visible points' jittered rays go
// to the engine callback in batches on the executor (stages 1-3,
// CallbackTrace); every pixel is a k-tap gather over the canvas tables (stage
// 4, GatherReconstruction); the temporal history the settings choose follows
// (stage 5), and the encode into the frame's RGBA8 rows (stage 6). The
// device's set (gpu::make_device_stages) records the same stages into the
// frame's command buffer. With reconstruct_on_cpu = false, render() without
// resources stops after the history's decision and the caller takes
// hand_off() (a reconstruction elsewhere: tests and benchmarks).
//
// Lifetime and threads: a FoveatedView belongs to one view (one eye of one
// display); render() is called from one thread at a time and spreads its work
// over the executor it is given. The tables are shared and immutable.
// Errors: render() never throws for anything the engine does (a failed batch or
// a NaN colour is reported in FrameResult); it throws std::invalid_argument
// when a request does not fit the tables (a programming error of the caller).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <glm/vec2.hpp>

#include "foveation/executor.hpp"
#include "foveation/foveation_centre.hpp"
#include "foveation/frame_stages.hpp"
#include "foveation/gather.hpp"
#include "foveation/ray_trace.h"
#include "foveation/view_settings.hpp"
#include "foveation/view_tables.hpp"

namespace foveart::foveation {

enum class FrameFailure : std::uint8_t {
  none = 0,
  callback_failed,  // the engine returned an error for a batch (or threw)
  invalid_colour,   // a colour component was NaN, infinite or negative
  resources_failed, // a stage could not run on the frame's resources (the wrong side, a device call failed)
};

struct FrameResult {
  FrameFailure failure = FrameFailure::none;
  std::string message;              // the failure, for a log line
  std::uint32_t points = 0;         // visible points traced
  std::uint32_t points_thinned = 0; // visible points of flat tiles filled from their parents (content density)
  std::uint64_t rays = 0;           // primary rays handed to the engine
  std::uint64_t failed_batches = 0;
  std::uint64_t invalid_colours = 0;  // colour components
  double select_ms = 0.0;           // the frame's set-up (selection itself runs inside the trace pass)
  double trace_ms = 0.0;            // visible-point test, rays, engine callback, colour per point
  double density_ms = 0.0;          // content-aware density's part of select and trace (TraceStats::density_ms)
  DensityCost density;              // ... per stage (TraceStats::density)
  double reconstruct_ms = 0.0;      // gather
  double temporal_ms = 0.0;              // the temporal history
  double encode_ms = 0.0;           // the encode (on the device: recording it)
  glm::vec2 centre_px{};            // the foveation centre this frame used (ViewSettings::centre_deadband_deg)
  bool temporal_reset = false;           // a history is kept and restarted this frame
  std::uint64_t history_off_screen = 0;   // TemporalMode::image: pixels whose surface was off the last view
  std::uint64_t history_disoccluded = 0;  // ... whose last depth disagreed (a surface uncovered)
  std::uint64_t history_with_depth = 0;   // ... reprojected through the engine's depth (the rest: rotation only)
  // TemporalMode::rays: the cache restarts this frame (a restart the cache
  // is not kept through, a failed frame before it, or the first frame).
  bool ray_cache_restart = false;
  GatherStats gather;

  bool ok() const { return failure == FrameFailure::none; }
};

class FoveatedView {
 public:
  FoveatedView(std::shared_ptr<const ViewTables> tables, const ViewSettings& settings);
  // The same with a temporal history made by the caller (the lab's variants of
  // the product's modes) instead of make_temporal_history(settings); null: that.
  FoveatedView(std::shared_ptr<const ViewTables> tables, const ViewSettings& settings,
               std::unique_ptr<TemporalHistory> history);
  // A frame of these stages (make_cpu_stages, gpu::make_device_stages), chosen once.
  FoveatedView(std::shared_ptr<const ViewTables> tables, const ViewSettings& settings, FrameStages stages);

  // One frame. On success image() holds it; on failure image() keeps the last
  // good frame and the temporal history restarts.
  FrameResult render(const FrameRequest& request, FoveartTraceRaysFn trace_rays, void* user_data,
                     Executor& executor);
  // One frame of every stage into `resources`, the side the stages were made
  // for (a resources_failed frame otherwise). trace_rays may be null when the
  // trace stage calls none (a device trace).
  FrameResult render(const FrameRequest& request, FoveartTraceRaysFn trace_rays, void* user_data,
                     FrameResources& resources, Executor& executor);

  // A frame traced elsewhere by a caller that records the device's frame
  // itself (tests, benchmarks; the device's stage set needs none): the
  // frame's canvas mapping, jitter seed and the history's decision,
  // in hand_off(), with no traced points (a ray history decides its restart
  // only: the device makes its rays and pixels). Needs reconstruct_on_cpu =
  // false (throws std::invalid_argument otherwise).
  FrameResult plan(const FrameRequest& request, Executor& executor);
  // A frame failed where it was traced (a fault the device reported frames
  // later): the next frame restarts the history.
  void forget_history() { history_->forget(); }

  // The last successful frame (after the temporal history), in the callback's
  // colour space (linear RGB from an engine).
  const ImageRgb& image() const { return host_.output != nullptr ? *host_.output : host_.reconstructed; }
  // The same frame before the history: the reconstruction alone.
  const ImageRgb& reconstructed() const { return host_.reconstructed; }
  // What a reconstruction elsewhere takes from the last frame (stage 3's
  // points, stage 5's decision): valid until the next render().
  const FrameHandOff& hand_off() const { return hand_off_; }
  // A ray history's kept rays after the last frame (0: another history).
  std::size_t cached_rays() const { return history_->kept_rays(); }
  const ViewTables& tables() const { return *tables_; }
  const ViewSettings& settings() const { return settings_; }
  // What the history blends with: settings().temporal_options for its rays per
  // point (temporal_options_for_rays).
  TemporalOptions temporal_options() const { return settings_.blend_options(); }

 private:
  std::shared_ptr<const ViewTables> tables_;
  ViewSettings settings_;
  FoveationCentre centre_;  // held through fixations (ViewSettings::centre_deadband_deg)
  std::unique_ptr<TemporalHistory> history_;   // stage 5
  std::unique_ptr<TraceStage> trace_;          // stages 1-3
  std::unique_ptr<ReconstructStage> reconstruct_;  // stage 4
  std::unique_ptr<EncodeStage> encode_;        // stage 6
  // The frame's context: the request checked against the tables, the centre moved.
  FrameContext begin_frame(const FrameRequest& request, FrameResult* result);
  // begin_frame with the engine's callback, then run_trace: false when the trace failed.
  bool begin_traced(const FrameRequest& request, FoveartTraceRaysFn trace_rays, void* user_data,
                    FrameResources& resources, Executor& executor, FrameContext* frame, FrameResult* result);
  // Stages 1-3 into `result`: false (the history forgotten) when the trace failed.
  bool run_trace(const FrameContext& frame, FrameResources& resources, Executor& executor, FrameResult* result);
  // Stages 4-6: false (the history forgotten) when a stage failed on the resources.
  bool run_after_trace(const FrameContext& frame, FrameResources& resources, Executor& executor,
                       FrameResult* result);
  void finish(FrameResult* result) const;  // the history's decision into the result

  HostFrame host_;  // render() without resources: image()
  TracedPoints nothing_traced_;  // plan()'s hand-off
  FrameHandOff hand_off_;
};

// The temporal history (stage 5) that `settings` choose, for `tables`.
std::unique_ptr<TemporalHistory> make_temporal_history(const ViewTables& tables, const ViewSettings& settings);
// Stages 1-3 through the engine's callback as `settings` choose (content
// density unless the history keeps rays); both sides' sets trace with it.
std::unique_ptr<TraceStage> make_callback_trace(std::shared_ptr<const ViewTables> tables, const ViewSettings& settings,
                                                bool keep_rays);
// The CPU's stage set; `history` null: make_temporal_history's.
FrameStages make_cpu_stages(std::shared_ptr<const ViewTables> tables, const ViewSettings& settings,
                            std::unique_ptr<TemporalHistory> history = nullptr);

}  // namespace foveart::foveation
