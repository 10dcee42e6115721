// The frame path's state of one FoveatedRenderer (renderer.hpp): tables per
// view size, per eye its path, view and device resources, the frames in
// flight, and the app-recorded trace's batch. Private to the layer: its
// methods live in foveated_renderer.cpp (the frame) and app_trace_frames.cpp
// (the app-recorded trace's acquire and its xrEndFrame).
#pragma once

#include <array>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <exception>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <tuple>
#include <vector>

#include "device_trace_engine.hpp"
#include "eye_swapchain.hpp"
#include "foveation/foveated_view.hpp"
#include "frame_submission.hpp"
#include "gaze_source.hpp"
#include "gpu/device_stages.hpp"
#include "gpu/reconstructor.hpp"
#include "ray_batch.hpp"
#include "renderer.hpp"

namespace foveart::layer {

using Clock = std::chrono::steady_clock;
inline float ms_since(Clock::time_point t0) {
  return std::chrono::duration<float, std::milli>(Clock::now() - t0).count();
}
inline int64_t steady_now_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now().time_since_epoch()).count();
}

struct FoveatedRenderer::Frames {
  using TableKey = std::tuple<uint32_t, uint32_t, int64_t>;  // w, h, horizontal FOV in micro-radians
  enum class SlotState { queued, building, ready, failed };
  struct TableSlot {
    SlotState state = SlotState::queued;
    std::shared_ptr<const foveation::ViewTables> ready;  // when state == ready
    uint64_t last_used = 0;  // frame index, for LRU eviction
  };
  struct Tables {
    std::shared_ptr<const foveation::ViewTables> ready;  // null: not (yet) there
    bool failed = false;  // the build failed: this view size falls back for good
  };
  // How an eye makes its frames, chosen once (choose_path) and again only after
  // its GPU path failed: which stage set its view runs (the CPU's or the
  // device's, foveation/frame_stages.hpp) and the frame resources they run on.
  // The per-eye frame code calls it without asking which.
  struct EyePath {
    bool reconstruct_on_gpu = false;
    bool device_trace = false;  // stages 1-3 on the device (the engine's device trace)
    // The view's stage set, made with the view.
    std::function<foveation::FrameStages(const std::shared_ptr<const foveation::ViewTables>& view_tables,
                                         const foveation::ViewSettings& view_settings)>
        stages;
    // This frame's resources for them (null: the frame falls back, counted and logged).
    std::function<foveation::FrameResources*(uint32_t e,
                                             const std::shared_ptr<const foveation::ViewTables>& view_tables,
                                             XrFoveatedRendererStatsFOVEART* stats)>
        resources;
    // The stages could not run on the resources: counted and logged (the GPU path falls back to the CPU).
    std::function<void(uint32_t e, const std::string& error, XrFoveatedRendererStatsFOVEART* stats)> resources_failed;
    // The frame after its stages into the swapchain: uploaded, or recorded for the slot's submission.
    std::function<bool(uint32_t e, XrFoveatedRendererStatsFOVEART* stats)> present;
  };
  struct Eye {
    std::shared_ptr<EyeSwapchain> swapchain;
    std::unique_ptr<foveation::FoveatedView> view;
    std::shared_ptr<gpu::Tables> gpu_tables;  // GPU path: the view's tables on the device
    std::shared_ptr<gpu::Eye> gpu_eye;      // GPU path: this eye's buffers and stages
    // GPU path: gpu_eye's shown image holds a good frame (the host read its
    // status). Until then a device-traced frame is waited for in xrEndFrame.
    bool shown_good = false;
    bool image_acquired = false;  // this frame's swapchain image, released after the submission
    // The last finished GPU frame's stage times and device-trace status (an older frame).
    std::optional<gpu::StageTimes> times;
    std::optional<gpu::DeviceTraceStatus> status;
    bool gpu_failed = false;  // the GPU path failed for this eye: the CPU reconstructs from now on
    std::optional<EyePath> path;  // chosen at the eye's first frame (choose_path)
    foveation::HostFrame host;    // the CPU path's frame resources
    gpu::DeviceFrame device;      // the GPU path's, this frame's
    bool failed = false;  // swapchain creation failed: this eye falls back for good
    foveation::TemporalMode temporal = foveation::TemporalMode::off;  // of `view`
  };

  Frames(std::shared_ptr<SessionState> session_in, const RendererSettings& settings_in, InputCounters& input_in,
         ReconstructionStats& reconstruction_in, DensityStats& density_in);
  ~Frames();

  uint32_t render(XrTime display_time, const XrCompositionLayerProjection& layer, XrCompositionLayerProjectionView* views,
                  const std::vector<bool>& rect_valid, const XrFoveatedDisplayTransformFOVEART* chained_display,
                  XrFoveatedRendererStatsFOVEART* stats);
  // The gaze predicted for display_time (XrTime on Linux runtimes is
  // CLOCK_MONOTONIC; a clock far away, a virtual runtime clock, is replaced
  // by now), and the frame's gaze stats.
  FrameGaze gaze_at(XrTime display_time, XrSpace space, const XrCompositionLayerProjectionView* views,
                    uint32_t view_count, XrFoveatedRendererStatsFOVEART* stats);
  // The app-recorded trace (ray_batch.hpp, the extension header).
  XrResult acquire(const XrFoveatedRayBatchAcquireInfoFOVEART& info, XrFoveatedRayBatchFOVEART* out,
                   XrFoveatedRendererStatsFOVEART* stats);
  // Why the acquire is refused (its error and *why), or XR_SUCCESS.
  XrResult acquire_refusal(const XrFoveatedRayBatchAcquireInfoFOVEART& info, XrFoveatedRayBatchFOVEART* out,
                           std::string* why) const;
  // Eye e's plan and rays at the acquire into `cb`; false (out left empty) when the view is not traced.
  bool plan_app_eye(uint32_t e, const FrameGaze& gaze, const XrView& view, XrExtent2Di size_px, VkCommandBuffer cb,
                    XrFoveatedDeviceRayBatchFOVEART* out, XrFoveatedRendererStatsFOVEART* stats);
  // xrEndFrame took the acquired batch: its age and, unreleased, its count.
  void took_batch(const TakenRayBatch& taken, XrFoveatedRendererStatsFOVEART* stats);
  // Eye e's frame from the app's trace: false when the view shows the app's own image.
  bool render_app_eye(uint32_t e, const TakenRayBatch& taken, XrCompositionLayerProjectionView& view,
                      XrFoveatedRendererStatsFOVEART* stats);
  void app_trace_stats(XrFoveatedAppTraceStatsFOVEART* out) const;
  Tables tables_for(const FoveartEyeView& view);
  void evict_least_recently_used();  // under build_mutex
  void build_tables();
  void cache_problem(const std::string& message);
  void choose_reconstruction();
  std::shared_ptr<gpu::Tables> gpu_tables_for(const std::shared_ptr<const foveation::ViewTables>& view_tables,
                                            std::string* error);
  // Eye e's frame begun on the device (its device stages' first recording): the
  // eye's buffers and tables, the frame slot's command buffer, its swapchain image acquired.
  VkCommandBuffer begin_on_gpu(uint32_t e, const std::shared_ptr<const foveation::ViewTables>& view_tables,
                               bool device_trace, gpu::DeviceFrame& frame, std::string* error);
  // Eye e's tables and buffers on the device for these tables and its swapchain's size.
  bool ensure_gpu_eye(uint32_t e, const std::shared_ptr<const foveation::ViewTables>& view_tables, std::string* error);
  // Eye e's app-traced frame, from its view's hand-off (no engine: the app traces).
  gpu::DeviceTraceFrame device_frame(uint32_t e, const foveation::FrameRequest& request,
                                     const std::shared_ptr<const foveation::ViewTables>& view_tables);
  // What a finished device-traced frame's resolve found: false (counted, logged once) when it faulted.
  bool device_trace_ok(uint32_t e, const gpu::DeviceTraceStatus& status, XrFoveatedRendererStatsFOVEART* stats);
  // The slot's last submission (kFrameSlots frames ago): waited for, its eyes'
  // status and stage times read and applied; `faulted`: the eyes whose trace faulted.
  void collect(uint32_t slot, XrFoveatedRendererStatsFOVEART* stats, std::array<bool, 2>* faulted = nullptr);
  // The eye's last collected GPU times and status into this frame's stats.
  void apply_collected(uint32_t e, XrFoveatedRendererStatsFOVEART* stats);
  // After the eyes: the slot's one submission, the images released, and the
  // device-traced eyes without a good shown image waited for; the views that
  // fall back after all get the app's sub-image back. Returns how many.
  uint32_t finish_gpu_frame(uint32_t slot, XrCompositionLayerProjectionView* views,
                            const XrSwapchainSubImage* app_sub_images, XrFoveatedRendererStatsFOVEART* stats);
  // False (flagged, logged once) when eye e's view cannot be traced (foveation::eye_view_problem);
  // `where` names the call that brought it.
  bool view_traceable(uint32_t e, const FoveartEyeView& view, const char* where, XrFoveatedRendererStatsFOVEART* stats);
  // One eye's frame, in the steps below, from `submitted`, the view the app submitted as
  // eye_view_of makes it (view_traceable passed it): false when the view shows the app's own image.
  bool render_eye(uint32_t e, const FrameGaze& gaze, const FoveartEyeView& submitted,
                  XrCompositionLayerProjectionView& view, XrFoveatedRendererStatsFOVEART* stats);
  bool ensure_swapchain(uint32_t e, uint32_t w, uint32_t h, XrFoveatedRendererStatsFOVEART* stats);
  // The eye's path: the GPU where the reconstructor runs and the eye's GPU path has not failed,
  // with the engine's device trace where it registered one; else the CPU with its callback.
  // False when neither can run (a device trace alone, and no GPU path).
  bool choose_path(uint32_t e);
  void choose_gpu_path(EyePath& path);  // the device's stage set and resources
  void choose_cpu_path(EyePath& path);  // the CPU's
  // The eye's FoveatedView for these tables and its path (made again when either changes).
  void ensure_view(uint32_t e, const std::shared_ptr<const foveation::ViewTables>& view_tables);
  // The request's frame, restart flags and foveation centre from this frame's gaze.
  void aim_at_gaze(uint32_t e, const FrameGaze& gaze, foveation::FrameRequest& request,
                   XrFoveatedRendererStatsFOVEART* stats);
  // The eye's stages 1-6 on the path's resources, and their stats.
  bool run_frame(uint32_t e, const foveation::FrameRequest& request,
                 const std::shared_ptr<const foveation::ViewTables>& view_tables,
                 XrFoveatedRendererStatsFOVEART* stats);
  // The paths' resources and present (EyePath).
  foveation::FrameResources* gpu_resources(uint32_t e, const std::shared_ptr<const foveation::ViewTables>& view_tables,
                                           bool device_trace);
  foveation::FrameResources* cpu_resources(uint32_t e, XrFoveatedRendererStatsFOVEART* stats);
  void fall_back_to_cpu(uint32_t e, const std::string& error, XrFoveatedRendererStatsFOVEART* stats);
  void upload_failed(uint32_t e, const std::string& error, XrFoveatedRendererStatsFOVEART* stats);
  bool present_gpu(uint32_t e, XrFoveatedRendererStatsFOVEART* stats);
  // A frame's result into the stats: false (logged once) when it failed.
  bool take_result(uint32_t e, const foveation::FrameResult& result, XrFoveatedRendererStatsFOVEART* stats);
  void take_density(uint32_t e, const foveation::FrameResult& result);
  // One eye's frame step (a render or an app-recorded plan) and its result; a
  // table/view inconsistency it throws makes the view fall back (frame_path_error).
  template <class Step>
  bool run_step(uint32_t e, XrFoveatedRendererStatsFOVEART* stats, Step&& step) {
    foveation::FrameResult result;
    try {
      result = step();
    } catch (const std::exception& error) {
      frame_path_error(e, error, stats);
      return false;
    }
    return take_result(e, result, stats);
  }
  void frame_path_error(uint32_t e, const std::exception& error, XrFoveatedRendererStatsFOVEART* stats);
  // The app-recorded trace: eye e's plan at the acquire (stages 1-5's decisions), and its stats.
  bool plan_app_frame(uint32_t e, const foveation::FrameRequest& request, XrFoveatedRendererStatsFOVEART* stats);
  // ... and its frame recorded at xrEndFrame (the resolve of the app's colours, stages 4-6).
  bool present_app_frame(uint32_t e, XrFoveatedRendererStatsFOVEART* stats);
  bool present_cpu(uint32_t e, XrFoveatedRendererStatsFOVEART* stats);
  // The view shows eye e's layer swapchain image.
  void show_layer_image(uint32_t e, XrCompositionLayerProjectionView& view) const;

  std::shared_ptr<SessionState> session;
  RendererSettings settings;
  InputCounters& input;  // the renderer's; outlives this
  ReconstructionStats& reconstruction;  // the renderer's; written under its frame lock
  DensityStats& density;                // the renderer's; likewise
  std::optional<std::filesystem::path> cache;  // null: no usable cache directory
  foveation::Executor executor;  // frames and table builds share its workers
  std::unique_ptr<GazeSource> gaze;
  // Tables per view size, built one after another on the builder thread
  // (seconds each): frames never wait for them unless wait_for_tables. At most
  // kMaxTableSets (renderer_tables.cpp) are held; the least recently used goes first.
  std::mutex build_mutex;
  std::condition_variable build_wake, build_done;
  std::deque<std::pair<TableKey, foveation::PointSetKey>> build_queue;
  std::map<TableKey, TableSlot> tables;
  bool stop_building = false;
  std::atomic<bool> cancel_build{false};  // the build in progress is not needed any more
  std::thread builder;  // started once with the renderer
  std::unique_ptr<gpu::Reconstructor> reconstructor;  // null: the CPU reconstructs
  std::vector<std::shared_ptr<gpu::Tables>> gpu_tables;  // uploaded table sets, shared by the eyes
  Eye eyes[2];  // after reconstructor: destroyed before it
  // What a slot's submission uses, kept alive until it finished, and what is read after it.
  struct InFlightEye {
    std::shared_ptr<gpu::Eye> gpu_eye;
    std::shared_ptr<gpu::Tables> tables;
    std::shared_ptr<EyeSwapchain> swapchain;
    bool recorded = false;      // recorded in full: its status and times are read
    bool device_trace = false;  // its status says whether the trace faulted
    bool shown = false;         // shown when submitted (pipelined): a fault is a fallback counted later
  };
  std::array<std::array<std::optional<InFlightEye>, 2>, gpu::kFrameSlots> in_flight;
  std::unique_ptr<FrameSubmission> submission;  // with the reconstructor; destroyed first: waits for the slots
  uint64_t frame_index = 0;
  // The app-recorded trace: the frame's batch, and per eye what its rays were
  // made for at the acquire (its batch's view points into it until the next acquire).
  struct AppEye {
    foveation::FrameRequest request;
    std::shared_ptr<const foveation::ViewTables> tables;
    gpu::DeviceTraceFrame device;
    std::unique_ptr<XrDeviceRayBatch> handed;  // the batch's view as handed to the app, its chain in here
  };
  RayBatches batches;
  std::array<std::optional<AppEye>, 2> app_eyes;
  bool frame_started = false;  // an acquire counted the next frame already
  XrFoveatedFallbackFlagsFOVEART acquire_flags = 0;  // why the acquire's views were not traced
  float acquired_gaze_age_ms = 0.0f;
  float acquire_to_end_frame_ms = 0.0f;
  uint64_t mismatched_views = 0;
  XrResult device_engine_result = XR_SUCCESS;  // the engine's last device trace's (xr_device_trace_engine)
  foveation::DisplayTransform display;  // this frame's (resolve_display)
  LogOnce display_once, callback_once, colour_once, upload_once, internal_once, rejected_once, unwritable_once,
      evicted_once, behind_once, rect_once, view_once, failed_once, gpu_once, submit_once;
  LogOnce app_once, unreleased_once, mismatch_once;  // the app-recorded trace's
  LogOnce cpu_render_cache_once;                     // temporal "rays" (config or app) reconstructed on the CPU
};

}  // namespace foveart::layer
