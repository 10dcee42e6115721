#include "foveation/foveated_view.hpp"

#include <chrono>
#include <numbers>
#include <stdexcept>

#include "foveation/callback_trace.hpp"
#include "foveation/gather_reconstruction.hpp"
#include "foveation/image_history.hpp"
#include "foveation/ray_history.hpp"
#include "foveation/elapsed.hpp"

namespace foveart::foveation {
namespace {

using Clock = std::chrono::steady_clock;

const ViewTables& checked(const std::shared_ptr<const ViewTables>& tables) {
  if (tables == nullptr) throw std::invalid_argument("foveated view: no tables");
  return *tables;
}

}  // namespace

std::unique_ptr<TemporalHistory> make_temporal_history(const ViewTables& tables, const ViewSettings& settings) {
  const TemporalOptions blend = settings.blend_options();
  switch (settings.temporal) {
    case TemporalMode::off: return std::make_unique<NoHistory>(blend);
    case TemporalMode::image: return std::make_unique<ImageHistory>(tables.neighbors, blend, /*reproject=*/true);
    case TemporalMode::rays: break;
  }
  return std::make_unique<RayHistory>(
      tables, blend, RayHistoryOptions{settings.pixel_filter, settings.ray_cache_max_age_frames});
}

FoveatedView::FoveatedView(std::shared_ptr<const ViewTables> tables, const ViewSettings& settings)
    : FoveatedView(std::move(tables), settings, nullptr) {}

FoveatedView::FoveatedView(std::shared_ptr<const ViewTables> tables, const ViewSettings& settings,
                           std::unique_ptr<TemporalHistory> history)
    : tables_(std::move(tables)),
      settings_(settings),
      centre_(settings.centre_deadband_deg * checked(tables_).key.display.view_distance_px * std::numbers::pi / 180.0) {
  if (settings_.rays_per_point < 1) throw std::invalid_argument("foveated view: rays per point must be >= 1");
  history_ = history != nullptr ? std::move(history) : make_temporal_history(*tables_, settings_);
  auto trace = std::make_unique<CallbackTrace>(tables_->points, settings_.rays_per_point, settings_.pixel_filter,
                                               settings_.new_jitter_each_frame, history_->keeps_rays());
  if (settings_.content_density.enabled() && !history_->keeps_rays()) {
    trace->set_content_density([tables = tables_](Executor& executor) -> const PointLevels& {
      return tables->levels(executor);
    }, settings_.content_density);
  }
  trace_ = std::move(trace);
  reconstruct_ = std::make_unique<GatherReconstruction>(*tables_, settings_.rbf_clamp);
  hand_off_.traced = &trace_->traced();
  hand_off_.rbf_clamp = settings_.rbf_clamp;
}

FrameContext FoveatedView::begin_frame(const FrameRequest& request, FrameResult* result) {
  const DisplayModel& display = tables_->key.display;
  const FoveartEyeView& view = request.view;
  if (view.width_px != std::uint32_t(display.width_px) || view.height_px != std::uint32_t(display.height_px)) {
    throw std::invalid_argument("foveated view: a " + std::to_string(view.width_px) + "x" +
                                std::to_string(view.height_px) + " view for tables of a " +
                                std::to_string(display.width_px) + "x" + std::to_string(display.height_px) + " display");
  }
  FrameContext frame;
  frame.view = view;
  frame.mapping = map_gaze(int(view.width_px), int(view.height_px),
                           centre_.update(request.gaze_px, request.saccade || request.blink));
  frame.frame_index = request.frame_index;
  frame.sample_seed = settings_.frame_sample_seed(request.frame_index);
  frame.restart = request.saccade || request.blink;
  result->centre_px = frame.mapping.gaze_px;
  hand_off_.mapping = frame.mapping;
  hand_off_.view = view;
  hand_off_.sample_seed = frame.sample_seed;
  hand_off_.temporal = TemporalFrame{};
  return frame;
}

FrameResult FoveatedView::plan(const FrameRequest& request, Executor& executor) {
  if (settings_.reconstruct_on_cpu)
    throw std::invalid_argument("foveated view: a frame traced on the device needs the GPU reconstruction");
  FrameResult result;
  const auto t_decide = Clock::now();
  const FrameContext frame = begin_frame(request, &result);
  hand_off_.traced = &nothing_traced_;
  hand_off_.temporal = history_->decide(frame, nothing_traced_, executor);
  result.temporal_ms = ms_since(t_decide);
  result.temporal_reset = hand_off_.temporal.kept && hand_off_.temporal.reset;
  return result;
}

FrameResult FoveatedView::render(const FrameRequest& request, FoveartTraceRaysFn trace_rays, void* user_data,
                                 Executor& executor) {
  if (trace_rays == nullptr) throw std::invalid_argument("foveated view: no ray-trace callback");
  FrameResult result;
  const auto t_frame = Clock::now();
  FrameContext frame = begin_frame(request, &result);
  frame.trace_rays = trace_rays;
  frame.user_data = user_data;
  hand_off_.traced = &trace_->traced();
  const double setup_ms = ms_since(t_frame);

  // Stages 1-3.
  const TraceStats traced = trace_->trace(frame, executor);
  result.select_ms = setup_ms + traced.select_ms;
  result.trace_ms = traced.trace_ms;
  result.points = traced.points;
  result.points_thinned = traced.points_thinned;
  result.density_ms = traced.density_ms;
  result.rays = traced.rays;
  result.failed_batches = traced.failed_batches;
  result.invalid_colours = traced.invalid_colours;
  if (!traced.ok()) {
    result.failure = traced.failed_batches != 0 ? FrameFailure::callback_failed : FrameFailure::invalid_colour;
    result.message = traced.failed_batches != 0
                         ? "the ray-trace callback failed " + std::to_string(traced.failed_batches) + " batch(es)"
                         : "the ray-trace callback returned " + std::to_string(traced.invalid_colours) +
                               " NaN/Inf/negative colour components";
    history_->forget();
    return result;
  }
  const TracedPoints& points = trace_->traced();
  TemporalFrame& temporal = hand_off_.temporal;
  if (!settings_.reconstruct_on_cpu) {  // the caller reconstructs: only the history's decision runs here
    const auto t_decide = Clock::now();
    temporal = history_->decide(frame, points, executor);
    result.temporal_ms = ms_since(t_decide);
  } else {
    const auto t_gather = Clock::now();  // stage 4
    result.gather = reconstruct_->reconstruct(frame, points, reconstructed_, executor);
    result.reconstruct_ms = ms_since(t_gather);
    const auto t_history = Clock::now();  // stage 5
    output_ = &history_->accumulate(frame, points, reconstructed_, executor, &temporal);
    result.temporal_ms = ms_since(t_history);
  }
  result.temporal_reset = temporal.kept && temporal.reset;
  result.ray_cache_restart = temporal.rays && temporal.ray_restart;
  result.history_off_screen = temporal.history_off_screen;
  result.history_disoccluded = temporal.history_disoccluded;
  result.history_with_depth = temporal.history_with_depth;
  return result;
}

}  // namespace foveart::foveation
