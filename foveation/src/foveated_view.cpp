#include "foveation/foveated_view.hpp"

#include <chrono>
#include <numbers>
#include <stdexcept>

#include "foveation/callback_trace.hpp"
#include "foveation/gather_reconstruction.hpp"
#include "foveation/host_encode.hpp"
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

std::unique_ptr<TraceStage> make_callback_trace(std::shared_ptr<const ViewTables> tables, const ViewSettings& settings,
                                                bool keep_rays) {
  if (settings.rays_per_point < 1) throw std::invalid_argument("foveated view: rays per point must be >= 1");
  auto trace = std::make_unique<CallbackTrace>(checked(tables).points, settings.rays_per_point, settings.pixel_filter,
                                               settings.new_jitter_each_frame, keep_rays);
  if (settings.content_density.enabled()) {
    trace->set_content_density([tables](Executor& executor) -> const PointLevels& {
      return tables->levels(executor);
    }, settings.content_density);
  }
  return trace;
}

FrameStages make_cpu_stages(std::shared_ptr<const ViewTables> tables, const ViewSettings& settings,
                            std::unique_ptr<TemporalHistory> history) {
  FrameStages stages;
  stages.history = history != nullptr ? std::move(history) : make_temporal_history(checked(tables), settings);
  stages.trace = make_callback_trace(tables, settings, stages.history->keeps_rays());
  stages.reconstruct = std::make_unique<GatherReconstruction>(*tables, settings.rbf_clamp);
  stages.encode = std::make_unique<HostEncode>();
  return stages;
}

FoveatedView::FoveatedView(std::shared_ptr<const ViewTables> tables, const ViewSettings& settings)
    : FoveatedView(std::move(tables), settings, std::unique_ptr<TemporalHistory>{}) {}

FoveatedView::FoveatedView(std::shared_ptr<const ViewTables> tables, const ViewSettings& settings,
                           std::unique_ptr<TemporalHistory> history)
    : FoveatedView(tables, settings, make_cpu_stages(tables, settings, std::move(history))) {}

FoveatedView::FoveatedView(std::shared_ptr<const ViewTables> tables, const ViewSettings& settings, FrameStages stages)
    : tables_(std::move(tables)),
      settings_(settings),
      centre_(settings.centre_deadband_deg * checked(tables_).key.display.view_distance_px * std::numbers::pi / 180.0),
      history_(std::move(stages.history)),
      trace_(std::move(stages.trace)),
      reconstruct_(std::move(stages.reconstruct)),
      encode_(std::move(stages.encode)) {
  if (settings_.rays_per_point < 1) throw std::invalid_argument("foveated view: rays per point must be >= 1");
  if (history_ == nullptr || trace_ == nullptr || reconstruct_ == nullptr || encode_ == nullptr)
    throw std::invalid_argument("foveated view: a stage of the frame is missing");
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
  if (settings_.reconstruct_on_cpu) return render(request, trace_rays, user_data, host_, executor);
  // The caller reconstructs: only the trace and the history's decision run here.
  FrameResult result;
  FrameContext frame;
  if (!begin_traced(request, trace_rays, user_data, host_, executor, &frame, &result)) return result;
  const auto t_decide = Clock::now();
  hand_off_.temporal = history_->decide(frame, trace_->traced(), executor);
  result.temporal_ms = ms_since(t_decide);
  finish(&result);
  return result;
}

FrameResult FoveatedView::render(const FrameRequest& request, FoveartTraceRaysFn trace_rays, void* user_data,
                                 FrameResources& resources, Executor& executor) {
  FrameResult result;
  FrameContext frame;
  if (!begin_traced(request, trace_rays, user_data, resources, executor, &frame, &result) ||
      !run_after_trace(frame, resources, executor, &result))
    return result;
  finish(&result);
  return result;
}

bool FoveatedView::begin_traced(const FrameRequest& request, FoveartTraceRaysFn trace_rays, void* user_data,
                                FrameResources& resources, Executor& executor, FrameContext* frame,
                                FrameResult* result) {
  const auto t_frame = Clock::now();
  *frame = begin_frame(request, result);
  frame->trace_rays = trace_rays;
  frame->user_data = user_data;
  result->select_ms = ms_since(t_frame);
  return run_trace(*frame, resources, executor, result);
}

bool FoveatedView::run_trace(const FrameContext& frame, FrameResources& resources, Executor& executor,
                             FrameResult* result) {
  hand_off_.traced = &trace_->traced();
  const TraceStats traced = trace_->trace(frame, resources, executor);
  result->select_ms += traced.select_ms;
  result->trace_ms = traced.trace_ms;
  result->points = traced.points;
  result->points_thinned = traced.points_thinned;
  result->density_ms = traced.density_ms;
  result->density = traced.density;
  result->rays = traced.rays;
  result->failed_batches = traced.failed_batches;
  result->invalid_colours = traced.invalid_colours;
  if (traced.ok()) return true;
  if (traced.failed_batches != 0) {
    result->failure = FrameFailure::callback_failed;
    result->message = !traced.error.empty() ? traced.error  // the trace stage's own words (a device trace)
                                            : "the ray-trace callback failed " +
                                                  std::to_string(traced.failed_batches) + " batch(es)";
  } else if (traced.invalid_colours != 0) {
    result->failure = FrameFailure::invalid_colour;
    result->message = "the ray-trace callback returned " + std::to_string(traced.invalid_colours) +
                      " NaN/Inf/negative colour components";
  } else {
    result->failure = FrameFailure::resources_failed;
    result->message = traced.error;
  }
  history_->forget();
  return false;
}

bool FoveatedView::run_after_trace(const FrameContext& frame, FrameResources& resources, Executor& executor,
                                   FrameResult* result) {
  const TracedPoints& points = trace_->traced();
  std::string error;
  const auto t_gather = Clock::now();  // stage 4
  bool ok = reconstruct_->reconstruct(frame, points, resources, executor, &result->gather, &error);
  result->reconstruct_ms = ms_since(t_gather);
  const auto t_history = Clock::now();  // stage 5
  ok = ok && history_->apply(frame, points, resources, executor, &hand_off_.temporal, &error);
  result->temporal_ms = ms_since(t_history);
  const auto t_encode = Clock::now();  // stage 6
  ok = ok && encode_->encode(frame, resources, executor, &error);
  result->encode_ms = ms_since(t_encode);
  if (ok) return true;
  result->failure = FrameFailure::resources_failed;
  result->message = error;
  history_->forget();
  return false;
}

void FoveatedView::finish(FrameResult* result) const {
  const TemporalFrame& temporal = hand_off_.temporal;
  result->temporal_reset = temporal.kept && temporal.reset;
  result->ray_cache_restart = temporal.rays && temporal.ray_restart;
  result->history_off_screen = temporal.history_off_screen;
  result->history_disoccluded = temporal.history_disoccluded;
  result->history_with_depth = temporal.history_with_depth;
}

}  // namespace foveart::foveation
