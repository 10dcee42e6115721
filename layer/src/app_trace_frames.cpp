// The app-recorded trace's side of the frame path (the extension header's
// "app-recorded trace", ray_batch.hpp): the acquire plans each view and submits
// its rays, signalling the renderer's timeline semaphore; xrEndFrame records
// the resolve of the app's colours and stages 4-6 with gpu::Eye, its
// submission waiting for the app's value.
#include <cstdlib>
#include <string>
#include <vector>

#include "log.hpp"
#include "renderer_frames.hpp"
#include "xr_glm.hpp"

namespace foveart::layer {

XrResult FoveatedRenderer::Frames::acquire_refusal(const XrFoveatedRayBatchAcquireInfoFOVEART& info,
                                                   XrFoveatedRayBatchFOVEART* out, std::string* why) const {
  if (!settings.app_trace) {
    *why = "the renderer was created without an XrFoveatedAppTraceInfoFOVEART";
    return XR_ERROR_VALIDATION_FAILURE;
  }
  if (info.viewCount == 0 || info.views == nullptr || info.imageSizes == nullptr) {
    *why = "acquireInfo has no views or image sizes";
    return XR_ERROR_VALIDATION_FAILURE;
  }
  for (uint32_t v = 0; v < info.viewCount; ++v) {
    if (info.imageSizes[v].width <= 0 || info.imageSizes[v].height <= 0) {
      *why = "imageSizes[" + std::to_string(v) + "] is not positive";
      return XR_ERROR_VALIDATION_FAILURE;
    }
  }
  out->viewCountOutput = info.viewCount;
  if (out->viewCapacityInput < info.viewCount || out->views == nullptr) {
    *why = "batch->views holds fewer than acquireInfo->viewCount views";
    return XR_ERROR_SIZE_INSUFFICIENT;
  }
  if (reconstructor == nullptr || submission == nullptr) {
    *why = "this renderer reconstructs on the CPU (config \"reconstruction\", or a device the shaders cannot run on)";
    return XR_ERROR_FEATURE_UNSUPPORTED;
  }
  return XR_SUCCESS;
}

XrResult FoveatedRenderer::Frames::acquire(const XrFoveatedRayBatchAcquireInfoFOVEART& info,
                                           XrFoveatedRayBatchFOVEART* out, XrFoveatedRendererStatsFOVEART* stats) {
  std::string why;
  XrResult refused = acquire_refusal(info, out, &why);
  std::vector<RayBatchView> keys(info.viewCount);
  for (uint32_t v = 0; v < info.viewCount && XR_SUCCEEDED(refused); ++v)
    keys[v] = RayBatchView{info.views[v].pose, info.views[v].fov, info.imageSizes[v]};
  uint64_t id = 0, rays_ready = 0, traced = 0;
  if (XR_SUCCEEDED(refused)) refused = batches.acquire(steady_now_ns(), std::move(keys), &id, &rays_ready, &traced);
  if (refused == XR_ERROR_CALL_ORDER_INVALID)
    why = "a batch is out for this frame already (acquire once per xrEndFrame)";
  if (XR_FAILED(refused)) {
    if (app_once.first()) log(LogLevel::Error, "xrAcquireFoveatedRayBatchFOVEART: ", why, " (logged once)");
    return refused;
  }
  if (!frame_started) ++frame_index;  // the frame this batch belongs to
  frame_started = true;
  const uint32_t slot = uint32_t(frame_index % gpu::kFrameSlots);
  collect(slot, stats);  // its previous frame finished: the slot's buffers may be written
  const VkSemaphore semaphore = submission->timeline(batches.semaphore_generation(), &why);
  const VkCommandBuffer cb = semaphore == VK_NULL_HANDLE ? VK_NULL_HANDLE : submission->begin_rays(slot, &why);
  std::vector<XrCompositionLayerProjectionView> located(info.viewCount);
  for (uint32_t v = 0; v < info.viewCount; ++v) {
    located[v].type = XR_TYPE_COMPOSITION_LAYER_PROJECTION_VIEW;
    located[v].pose = info.views[v].pose;
    located[v].fov = info.views[v].fov;
  }
  XrFoveatedRendererStatsFOVEART at_acquire = *stats;  // xrEndFrame counts the frame's gaze; this one is the rays'
  const FrameGaze frame_gaze = gaze_at(info.displayTime, info.space, located.data(), info.viewCount, &at_acquire);
  acquired_gaze_age_ms = at_acquire.gazeAgeMs;
  stats->fallbackFlags = at_acquire.fallbackFlags;  // the acquired frame's, from here
  for (uint32_t v = 0; v < info.viewCount; ++v) {
    out->views[v] = XrFoveatedDeviceRayBatchFOVEART{};
    out->views[v].type = XR_TYPE_FOVEATED_DEVICE_RAY_BATCH_FOVEART;
    if (v < 2) app_eyes[v].reset();
    if (v < 2 && cb != VK_NULL_HANDLE)
      plan_app_eye(v, frame_gaze, info.views[v], info.imageSizes[v], cb, &out->views[v], stats);
  }
  acquire_flags = stats->fallbackFlags;
  if (cb == VK_NULL_HANDLE || !submission->submit_rays(slot, semaphore, rays_ready, &why)) {
    batches.withdraw();
    app_eyes = {};
    if (submit_once.first()) log(LogLevel::Error, "xrAcquireFoveatedRayBatchFOVEART: ", why, " (logged once)");
    return XR_ERROR_RUNTIME_FAILURE;
  }
  out->batchId = id;
  out->semaphore = semaphore;
  out->raysReadyValue = rays_ready;
  out->tracedValue = traced;
  return XR_SUCCESS;
}

bool FoveatedRenderer::Frames::plan_app_eye(uint32_t e, const FrameGaze& frame_gaze, const XrView& located,
                                            XrExtent2Di size_px, VkCommandBuffer cb,
                                            XrFoveatedDeviceRayBatchFOVEART* out,
                                            XrFoveatedRendererStatsFOVEART* stats) {
  Eye& eye = eyes[e];
  const auto w = static_cast<uint32_t>(size_px.width), h = static_cast<uint32_t>(size_px.height);
  AppEye app_eye;
  app_eye.request.view = eye_view_of(e, located.pose, located.fov, w, h);
  if (!view_traceable(e, app_eye.request.view, "xrAcquireFoveatedRayBatchFOVEART", stats)) return false;
  const Tables found = tables_for(app_eye.request.view);
  if (eye.failed || found.failed || found.ready == nullptr) {
    if (!eye.failed)
      stats->fallbackFlags |=
          found.failed ? XR_FOVEATED_FALLBACK_TABLES_FAILED_BIT_FOVEART : XR_FOVEATED_FALLBACK_WARMING_UP_BIT_FOVEART;
    return false;
  }
  if (!ensure_swapchain(e, w, h, stats)) return false;
  if ((!eye.path && !choose_path(e)) || !eye.path->device_trace) {
    stats->fallbackFlags |= XR_FOVEATED_FALLBACK_UNAVAILABLE_BIT_FOVEART;
    return false;
  }
  ensure_view(e, found.ready);
  aim_at_gaze(e, frame_gaze, app_eye.request, stats);
  if (!plan_app_frame(e, app_eye.request, stats)) return false;
  std::string error;
  gpu::DeviceRayBatch batch;
  bool made = ensure_gpu_eye(e, found.ready, &error);
  if (made) {
    app_eye.tables = found.ready;
    AppEye& kept = app_eyes[e].emplace(std::move(app_eye));
    kept.device = device_frame(e, kept.request, kept.tables);
    kept.device.app_trace = true;
    made = eye.gpu_eye->record_app_rays(cb, uint32_t(frame_index % gpu::kFrameSlots), *eye.gpu_tables, kept.device,
                                        &batch, &error);
  }
  if (!made) {
    app_eyes[e].reset();
    stats->fallbackFlags |= XR_FOVEATED_FALLBACK_UPLOAD_FAILED_BIT_FOVEART;
    if (gpu_once.first())
      log(LogLevel::Error, "foveated renderer: eye ", e, ": the rays cannot be made: ", error, " (logged once)");
    return false;
  }
  AppEye& kept = *app_eyes[e];
  kept.handed = std::make_unique<XrDeviceRayBatch>(batch);
  *out = kept.handed->batch;  // its `next` (footprint, addresses) points into kept.handed until the next acquire
  return true;
}

void FoveatedRenderer::Frames::took_batch(const TakenRayBatch& taken, XrFoveatedRendererStatsFOVEART* stats) {
  acquire_to_end_frame_ms = float(double(steady_now_ns() - taken.acquired_ns) * 1e-6);
  stats->fallbackFlags |= acquire_flags;
  if (stats->gazeAgeMs > 0.0f) stats->gazeAgeMs = acquired_gaze_age_ms + acquire_to_end_frame_ms;  // the rays' gaze
  if (taken.released) return;
  stats->fallbackFlags |= XR_FOVEATED_FALLBACK_CALLBACK_FAILED_BIT_FOVEART;
  if (unreleased_once.first()) {
    log(LogLevel::Error, "xrEndFrame: ray batch ", taken.id,
        taken.released_twice ? " was released twice" : " was not released",
        " (xrReleaseFoveatedRayBatchFOVEART); "
        "its views show the app's own image and it is retired (logged once, counted in the stats)");
  }
}

bool FoveatedRenderer::Frames::render_app_eye(uint32_t e, const TakenRayBatch& taken,
                                              XrCompositionLayerProjectionView& view,
                                              XrFoveatedRendererStatsFOVEART* stats) {
  Eye& eye = eyes[e];
  if (!app_eyes[e]) return false;  // not traced at the acquire (flags in acquire_flags)
  const RayBatchView shown{view.pose, view.fov, view.subImage.imageRect.extent};
  const bool same = e < taken.views.size() && same_view(taken.views[e], shown);
  if (taken.released && !same) {
    ++mismatched_views;
    stats->fallbackFlags |= XR_FOVEATED_FALLBACK_UNAVAILABLE_BIT_FOVEART;
    if (mismatch_once.first()) {
      log(LogLevel::Error, "xrEndFrame: eye ", e,
          ": its pose, fov or imageRect size differ from the ray batch's "
          "acquire; showing the app's own image (logged once, counted in the stats)");
    }
  }
  if (!taken.released || !same || !eye.path || !eye.path->device_trace) {
    if (eye.view != nullptr) eye.view->forget_history();  // its plan was not shown
    return false;
  }
  if (!present_app_frame(e, stats)) return false;
  show_layer_image(e, view);
  return true;
}

void FoveatedRenderer::Frames::app_trace_stats(XrFoveatedAppTraceStatsFOVEART* out) const {
  out->batchesAcquired = batches.acquired();
  out->unreleasedBatches = batches.retired();
  out->rejectedReleases = batches.rejected_releases();
  out->mismatchedViews = mismatched_views;
  out->acquireToEndFrameMs = acquire_to_end_frame_ms;
}

bool FoveatedRenderer::Frames::present_app_frame(uint32_t e, XrFoveatedRendererStatsFOVEART* stats) {
  Eye& eye = eyes[e];
  AppEye& app_eye = *app_eyes[e];
  const auto t0 = Clock::now();
  gpu::DeviceFrame begun;
  begun.slot = uint32_t(frame_index % gpu::kFrameSlots);
  std::string error;
  const VkCommandBuffer cb = begin_on_gpu(e, app_eye.tables, true, begun, &error);
  bool recorded = cb != VK_NULL_HANDLE;
  if (recorded) {
    // The plan's hand-off (the acquire's), resolved from the app's colours and reconstructed as a device trace's.
    gpu::EyeFrame frame = gpu::EyeFrame::of(*eye.gpu_tables, eye.view->hand_off(), eye.swapchain->srgb());
    frame.display = display;
    frame.device = &app_eye.device;
    frame.slot = begun.slot;
    recorded = eye.gpu_eye->record(cb, frame, begun.image, executor, &error);
  }
  stats->uploadMs[e] = ms_since(t0);
  if (!recorded) {
    fall_back_to_cpu(e, error, stats);
    return false;
  }
  return present_gpu(e, stats);
}

bool FoveatedRenderer::Frames::plan_app_frame(uint32_t e, const foveation::FrameRequest& request,
                                              XrFoveatedRendererStatsFOVEART* stats) {
  return run_step(e, stats, [&] { return eyes[e].view->plan(request, executor); });
}

gpu::DeviceTraceFrame FoveatedRenderer::Frames::device_frame(
    uint32_t e, const foveation::FrameRequest& request,
    const std::shared_ptr<const foveation::ViewTables>& view_tables) {
  const Eye& eye = eyes[e];
  const foveation::FrameHandOff& hand_off = eye.view->hand_off();
  gpu::DeviceTraceFrame device;
  device.points = &view_tables->points;
  device.view = request.view;
  device.mapping = hand_off.mapping;
  device.frame_index = frame_index;
  device.sample_seed = hand_off.sample_seed;
  device.rays_per_point = uint32_t(eye.view->settings().rays_per_point);
  device.pixel_filter = eye.view->settings().pixel_filter;
  device.density = eye.view->settings().content_density;
  if (device.density.enabled()) device.levels = &view_tables->levels(executor);  // built once per table set
  return device;
}

XrResult FoveatedRenderer::acquire_ray_batch(const XrFoveatedRayBatchAcquireInfoFOVEART& info,
                                             XrFoveatedRayBatchFOVEART* out_batch) {
  std::lock_guard lock(mutex_);
  if (frames_ == nullptr) return XR_ERROR_FEATURE_UNSUPPORTED;  // no Vulkan: create refused it already
  return frames_->acquire(info, out_batch, &stats_);
}

XrResult FoveatedRenderer::release_ray_batch(std::uint64_t batch_id) {
  std::lock_guard lock(mutex_);
  if (frames_ == nullptr) return XR_ERROR_VALIDATION_FAILURE;
  const XrResult result = frames_->batches.release(batch_id);
  if (XR_FAILED(result) && release_once_.first()) {
    log(LogLevel::Error, "xrReleaseFoveatedRayBatchFOVEART: batch ", batch_id,
        result == XR_ERROR_CALL_ORDER_INVALID ? " was retired unreleased at its xrEndFrame"
                                              : " is unknown or released already",
        " (logged once, counted in the stats)");
  }
  return result;
}

}  // namespace foveart::layer
