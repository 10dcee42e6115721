// Sessions: the state machine (IDLE -> READY -> SYNCHRONIZED -> VISIBLE ->
// FOCUSED, and back through STOPPING -> IDLE -> EXITING), the frame budget,
// and the frame loop (xrWaitFrame pacing at 70 Hz, blocking while the previous frame is
// not yet begun, so an app may wait on one thread and begin/end on another; xrBeginFrame,
// xrEndFrame).
#include "api_common.h"
#include "sim_runtime/sim_env.h"

namespace foveart::sim {

void push_event(Instance& inst, const XrEventDataBuffer& event) {
  constexpr size_t kMaxQueued = 256;
  if (inst.events.size() >= kMaxQueued) inst.events.pop_front();
  inst.events.push_back(event);
}

void set_session_state(Instance& inst, Session& s, XrSessionState state) {
  s.state = state;
  XrEventDataBuffer buffer{};
  buffer.type = XR_TYPE_EVENT_DATA_BUFFER;
  auto* e = reinterpret_cast<XrEventDataSessionStateChanged*>(&buffer);
  e->type = XR_TYPE_EVENT_DATA_SESSION_STATE_CHANGED;
  e->next = nullptr;
  e->session = to_handle<XrSession>(s.id);
  e->state = state;
  e->time = inst.clock.now_ns();
  push_event(inst, buffer);
  static const char* kNames[] = {"UNKNOWN", "IDLE",     "READY",        "SYNCHRONIZED", "VISIBLE",
                                 "FOCUSED", "STOPPING", "LOSS_PENDING", "EXITING"};
  if (state >= 0 && state <= XR_SESSION_STATE_EXITING) {
    log(LogLevel::Debug, std::string("session state ") + kNames[state]);
  }
}

void destroy_session_children(Runtime& rt, uint64_t session_id) {
  auto sit = rt.sessions.find(session_id);
  if (sit == rt.sessions.end()) return;
  Session& s = *sit->second;
  for (auto it = rt.swapchains.begin(); it != rt.swapchains.end();) {
    if (handle_id(it->second->session) == session_id) {
      for (auto& img : it->second->images) s.vk.destroy_image(img);
      it = rt.swapchains.erase(it);
    } else {
      ++it;
    }
  }
  for (auto it = rt.spaces.begin(); it != rt.spaces.end();) {
    it = handle_id(it->second->session) == session_id ? rt.spaces.erase(it) : std::next(it);
  }
  s.capture.reset();
  s.vk.destroy();
}

namespace {

// Runtime-initiated or app-requested exit: walk down to STOPPING.
void begin_exit(Instance& inst, Session& s) {
  s.exit_requested = true;
  if (s.state == XR_SESSION_STATE_FOCUSED) set_session_state(inst, s, XR_SESSION_STATE_VISIBLE);
  if (s.state == XR_SESSION_STATE_VISIBLE)
    set_session_state(inst, s, XR_SESSION_STATE_SYNCHRONIZED);
  if (s.state == XR_SESSION_STATE_SYNCHRONIZED || s.state == XR_SESSION_STATE_READY) {
    set_session_state(inst, s, XR_SESSION_STATE_STOPPING);
  }
}

XRAPI_ATTR XrResult XRAPI_CALL create_session(XrInstance instance, const XrSessionCreateInfo* info,
                                              XrSession* out) {
  return guarded("xrCreateSession", [&]() -> XrResult {
    FOVEART_LOCK_INSTANCE(instance);
    FOVEART_CHECK_STRUCT(info, XR_TYPE_SESSION_CREATE_INFO);
    if (out == nullptr) return XR_ERROR_VALIDATION_FAILURE;
    if (info->systemId != kSystemId) return XR_ERROR_SYSTEM_INVALID;
    if (!inst->ext_vulkan && !inst->ext_vulkan2)
      return XR_ERROR_GRAPHICS_DEVICE_INVALID;  // headless sessions unsupported
    if (!inst->graphics_requirements_queried) return XR_ERROR_GRAPHICS_REQUIREMENTS_CALL_MISSING;
    // XrGraphicsBindingVulkan2KHR is the same struct and type value as the v1 binding.
    const auto* binding =
        find_in_chain<XrGraphicsBindingVulkanKHR>(info->next, XR_TYPE_GRAPHICS_BINDING_VULKAN_KHR);
    if (binding == nullptr || binding->instance == VK_NULL_HANDLE ||
        binding->physicalDevice == VK_NULL_HANDLE || binding->device == VK_NULL_HANDLE) {
      return XR_ERROR_GRAPHICS_DEVICE_INVALID;
    }
    if (!rt.sessions.empty()) return XR_ERROR_LIMIT_REACHED;
    auto s = std::make_unique<Session>();
    std::string error;
    if (!s->vk.init(binding->instance, binding->physicalDevice, binding->device,
                    binding->queueFamilyIndex, binding->queueIndex, &error)) {
      log(LogLevel::Error, "xrCreateSession: " + error);
      return XR_ERROR_GRAPHICS_DEVICE_INVALID;
    }
    if (!inst->config.capture_dir.empty()) {
      s->capture = std::make_unique<FrameCapture>();
      if (!s->capture->open(inst->config.capture_dir, inst->config.capture_every, &error)) {
        log(LogLevel::Error, std::string(env::kCaptureDir) + ": " + error);
        s->vk.destroy();
        return XR_ERROR_RUNTIME_FAILURE;
      }
    }
    s->id = rt.next_id++;
    s->motion_origin_ns = inst->clock.now_ns();
    Session& ref = *s;
    rt.sessions.emplace(s->id, std::move(s));
    *out = to_handle<XrSession>(ref.id);
    set_session_state(*inst, ref, XR_SESSION_STATE_IDLE);
    set_session_state(*inst, ref, XR_SESSION_STATE_READY);
    return XR_SUCCESS;
  });
}

XRAPI_ATTR XrResult XRAPI_CALL destroy_session(XrSession handle) {
  return guarded("xrDestroySession", [&]() -> XrResult {
    FOVEART_LOCK_SESSION(handle);
    (void)inst;
    (void)session;
    destroy_session_children(rt, handle_id(handle));
    rt.sessions.erase(handle_id(handle));
    rt.frame_order_changed.notify_all();  // a blocked xrWaitFrame returns HANDLE_INVALID
    return XR_SUCCESS;
  });
}

XRAPI_ATTR XrResult XRAPI_CALL begin_session(XrSession handle, const XrSessionBeginInfo* info) {
  return guarded("xrBeginSession", [&]() -> XrResult {
    FOVEART_LOCK_SESSION(handle);
    FOVEART_CHECK_STRUCT(info, XR_TYPE_SESSION_BEGIN_INFO);
    if (info->primaryViewConfigurationType != XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO) {
      return XR_ERROR_VIEW_CONFIGURATION_TYPE_UNSUPPORTED;
    }
    if (session->running) return XR_ERROR_SESSION_RUNNING;
    if (session->state != XR_SESSION_STATE_READY) return XR_ERROR_SESSION_NOT_READY;
    session->running = true;
    session->motion_origin_ns = inst->clock.now_ns();  // the scripted motion starts here
    session->synchronized_sent = false;
    session->frame_waited = false;
    session->frame_begun = false;
    session->last_vsync_index = -1;
    rt.frame_order_changed.notify_all();
    return XR_SUCCESS;
  });
}

XRAPI_ATTR XrResult XRAPI_CALL end_session(XrSession handle) {
  return guarded("xrEndSession", [&]() -> XrResult {
    FOVEART_LOCK_SESSION(handle);
    if (!session->running) return XR_ERROR_SESSION_NOT_RUNNING;
    if (session->state != XR_SESSION_STATE_STOPPING) return XR_ERROR_SESSION_NOT_STOPPING;
    session->running = false;
    session->frame_waited = false;
    session->frame_begun = false;
    rt.frame_order_changed.notify_all();  // a blocked xrWaitFrame returns SESSION_NOT_RUNNING
    set_session_state(*inst, *session, XR_SESSION_STATE_IDLE);
    if (session->exit_requested) set_session_state(*inst, *session, XR_SESSION_STATE_EXITING);
    return XR_SUCCESS;
  });
}

XRAPI_ATTR XrResult XRAPI_CALL request_exit_session(XrSession handle) {
  return guarded("xrRequestExitSession", [&]() -> XrResult {
    FOVEART_LOCK_SESSION(handle);
    if (!session->running) return XR_ERROR_SESSION_NOT_RUNNING;
    begin_exit(*inst, *session);
    return XR_SUCCESS;
  });
}

XRAPI_ATTR XrResult XRAPI_CALL wait_frame(XrSession handle, const XrFrameWaitInfo* info,
                                          XrFrameState* state) {
  return guarded("xrWaitFrame", [&]() -> XrResult {
    FOVEART_LOCK_SESSION(handle);
    if (info != nullptr && info->type != XR_TYPE_FRAME_WAIT_INFO)
      return XR_ERROR_VALIDATION_FAILURE;
    FOVEART_CHECK_STRUCT(state, XR_TYPE_FRAME_STATE);
    if (!session->running) return XR_ERROR_SESSION_NOT_RUNNING;
    // OpenXR 1.0, xrWaitFrame: "A subsequent xrWaitFrame call must block until the previous
    // frame has been begun with xrBeginFrame" -- a pipelining app waits on one thread and
    // begins on another. Both clocks block here; the virtual one does not move meanwhile.
    if (session->frame_waited) {
      rt.frame_order_changed.wait(lock, [&] {
        session = find(rt.sessions, handle);
        return session == nullptr || !rt.instance || !session->running || !session->frame_waited;
      });
      if (session == nullptr || !rt.instance) return XR_ERROR_HANDLE_INVALID;
      inst = rt.instance.get();
      if (!session->running) return XR_ERROR_SESSION_NOT_RUNNING;
    }
    // Vsync grid t_k = origin + k * period; wake at the next unused slot, never
    // earlier than now (a late app skips slots instead of bursting).
    const int64_t now = inst->clock.now_ns();
    if (session->last_vsync_index < 0) {
      session->vsync_origin_ns = now;
    }
    const int64_t since = now - session->vsync_origin_ns;
    const int64_t due = (since + kFramePeriodNs - 1) / kFramePeriodNs;
    const int64_t k = std::max(session->last_vsync_index + 1, due);
    session->last_vsync_index = k;
    const int64_t wake_ns = session->vsync_origin_ns + k * kFramePeriodNs;
    if (inst->clock.is_virtual()) {
      inst->clock.sleep_until_ns(wake_ns);
    } else {
      const SimClock clock = inst->clock;
      lock.unlock();
      SimClock(clock).sleep_until_ns(wake_ns);
      lock.lock();
      session = find(rt.sessions, handle);
      if (session == nullptr || !rt.instance) return XR_ERROR_HANDLE_INVALID;
      inst = rt.instance.get();
    }
    if (!session->synchronized_sent && session->state == XR_SESSION_STATE_READY) {
      session->synchronized_sent = true;
      set_session_state(*inst, *session, XR_SESSION_STATE_SYNCHRONIZED);
      set_session_state(*inst, *session, XR_SESSION_STATE_VISIBLE);
      set_session_state(*inst, *session, XR_SESSION_STATE_FOCUSED);
    }
    session->frame_waited = true;
    session->predicted_display_ns = wake_ns + kFramePeriodNs;
    session->waited = FrameTiming{};
    session->waited.wait_return_ns = inst->clock.now_ns();
    session->waited.predicted_display_ns = session->predicted_display_ns;
    state->predictedDisplayTime = session->predicted_display_ns;
    state->predictedDisplayPeriod = kFramePeriodNs;
    state->shouldRender =
        (session->state == XR_SESSION_STATE_VISIBLE || session->state == XR_SESSION_STATE_FOCUSED)
            ? XR_TRUE
            : XR_FALSE;
    return XR_SUCCESS;
  });
}

XRAPI_ATTR XrResult XRAPI_CALL begin_frame(XrSession handle, const XrFrameBeginInfo* info) {
  return guarded("xrBeginFrame", [&]() -> XrResult {
    FOVEART_LOCK_SESSION(handle);
    if (info != nullptr && info->type != XR_TYPE_FRAME_BEGIN_INFO)
      return XR_ERROR_VALIDATION_FAILURE;
    if (!session->running) return XR_ERROR_SESSION_NOT_RUNNING;
    if (!session->frame_waited) return XR_ERROR_CALL_ORDER_INVALID;
    session->frame_waited = false;
    const bool discarded = session->frame_begun;
    session->frame_begun = true;
    session->current = session->waited;
    session->current.begin_ns = inst->clock.now_ns();
    rt.frame_order_changed.notify_all();  // a blocked xrWaitFrame may go on
    return discarded ? XR_FRAME_DISCARDED : XR_SUCCESS;
  });
}

XrResult check_swapchain_image(Runtime& rt, const Session& s, const XrSwapchainSubImage& sub,
                               Swapchain** out) {
  Swapchain* sc = find(rt.swapchains, sub.swapchain);
  if (sc == nullptr || handle_id(sc->session) != s.id) return XR_ERROR_HANDLE_INVALID;
  if (sc->last_released < 0) return XR_ERROR_LAYER_INVALID;  // nothing released yet
  const auto& r = sub.imageRect;
  if (r.offset.x < 0 || r.offset.y < 0 || r.extent.width <= 0 || r.extent.height <= 0 ||
      static_cast<int64_t>(r.offset.x) + r.extent.width > static_cast<int64_t>(sc->info.width) ||
      static_cast<int64_t>(r.offset.y) + r.extent.height > static_cast<int64_t>(sc->info.height)) {
    return XR_ERROR_SWAPCHAIN_RECT_INVALID;
  }
  if (sub.imageArrayIndex >= sc->info.arraySize) return XR_ERROR_VALIDATION_FAILURE;
  *out = sc;
  return XR_SUCCESS;
}

XrResult check_space(Runtime& rt, const Session& s, XrSpace space) {
  Space* sp = find(rt.spaces, space);
  return (sp == nullptr || handle_id(sp->session) != s.id) ? XR_ERROR_HANDLE_INVALID : XR_SUCCESS;
}

XrResult validate_layers(Runtime& rt, const Session& s, const XrFrameEndInfo& info,
                         uint32_t& projection_views) {
  projection_views = 0;
  if (info.layerCount > kMaxLayers) return XR_ERROR_LAYER_LIMIT_EXCEEDED;
  if (info.layerCount > 0 && info.layers == nullptr) return XR_ERROR_VALIDATION_FAILURE;
  for (uint32_t i = 0; i < info.layerCount; ++i) {
    const XrCompositionLayerBaseHeader* layer = info.layers[i];
    if (layer == nullptr) return XR_ERROR_LAYER_INVALID;
    if (XrResult r = check_space(rt, s, layer->space); r != XR_SUCCESS) return r;
    if (layer->type == XR_TYPE_COMPOSITION_LAYER_PROJECTION) {
      const auto* p = reinterpret_cast<const XrCompositionLayerProjection*>(layer);
      if (p->viewCount != 2 || p->views == nullptr) return XR_ERROR_VALIDATION_FAILURE;
      for (uint32_t v = 0; v < p->viewCount; ++v) {
        const XrCompositionLayerProjectionView& view = p->views[v];
        if (view.type != XR_TYPE_COMPOSITION_LAYER_PROJECTION_VIEW)
          return XR_ERROR_VALIDATION_FAILURE;
        if (!is_unit_quaternion(view.pose.orientation)) return XR_ERROR_POSE_INVALID;
        Swapchain* sc = nullptr;
        if (XrResult r = check_swapchain_image(rt, s, view.subImage, &sc); r != XR_SUCCESS)
          return r;
        if (sc->is_depth) return XR_ERROR_LAYER_INVALID;
        ++projection_views;
      }
    } else if (layer->type == XR_TYPE_COMPOSITION_LAYER_QUAD) {
      const auto* q = reinterpret_cast<const XrCompositionLayerQuad*>(layer);
      if (!is_unit_quaternion(q->pose.orientation)) return XR_ERROR_POSE_INVALID;
      Swapchain* sc = nullptr;
      if (XrResult r = check_swapchain_image(rt, s, q->subImage, &sc); r != XR_SUCCESS) return r;
    } else {
      return XR_ERROR_LAYER_INVALID;
    }
  }
  return XR_SUCCESS;
}

// Reads back every projection view of this frame into PNGs.
uint32_t capture_frame(Runtime& rt, Session& s, const XrFrameEndInfo& info, uint64_t frame) {
  uint32_t captured = 0;
  uint32_t projection_index = 0;
  std::vector<uint8_t> texels;
  for (uint32_t i = 0; i < info.layerCount; ++i) {
    if (info.layers[i]->type != XR_TYPE_COMPOSITION_LAYER_PROJECTION) continue;
    const auto* p = reinterpret_cast<const XrCompositionLayerProjection*>(info.layers[i]);
    for (uint32_t v = 0; v < p->viewCount; ++v) {
      const XrSwapchainSubImage& sub = p->views[v].subImage;
      Swapchain* sc = find(rt.swapchains, sub.swapchain);
      bool bgra = false;
      if (sc == nullptr || !is_capturable_format(static_cast<VkFormat>(sc->info.format), bgra)) {
        log(LogLevel::Info,
            "capture: skipping a view whose swapchain format is not 8-bit RGBA/BGRA");
        continue;
      }
      const SwapchainImage& img = sc->images[static_cast<size_t>(sc->last_released)];
      const auto& r = sub.imageRect;
      const auto w = static_cast<uint32_t>(r.extent.width);
      const auto h = static_cast<uint32_t>(r.extent.height);
      if (!img.initialized ||
          !s.vk.read_back(img, sub.imageArrayIndex, r.offset.x, r.offset.y, w, h, texels)) {
        log(LogLevel::Error, "capture: read back failed");
        continue;
      }
      const std::string path = s.capture->image_path(frame, projection_index, v);
      if (s.capture->write_png(path, texels, w, h, bgra)) {
        ++captured;
      } else {
        log(LogLevel::Error, "capture: cannot write " + path);
      }
    }
    ++projection_index;
  }
  return captured;
}

XRAPI_ATTR XrResult XRAPI_CALL end_frame(XrSession handle, const XrFrameEndInfo* info) {
  return guarded("xrEndFrame", [&]() -> XrResult {
    FOVEART_LOCK_SESSION(handle);
    FOVEART_CHECK_STRUCT(info, XR_TYPE_FRAME_END_INFO);
    if (!session->running) return XR_ERROR_SESSION_NOT_RUNNING;
    if (!session->frame_begun) return XR_ERROR_CALL_ORDER_INVALID;
    if (info->displayTime <= 0) return XR_ERROR_TIME_INVALID;
    if (info->environmentBlendMode != XR_ENVIRONMENT_BLEND_MODE_OPAQUE) {
      return XR_ERROR_ENVIRONMENT_BLEND_MODE_UNSUPPORTED;
    }
    uint32_t projection_views = 0;
    if (XrResult r = validate_layers(rt, *session, *info, projection_views); r != XR_SUCCESS) {
      log(LogLevel::Info, "xrEndFrame rejected a layer (XrResult " + std::to_string(r) + ")");
      return r;
    }
    session->frame_begun = false;
    const uint64_t frame = session->frames_ended++;
    FrameTiming& t = session->current;
    t.frame = frame;
    t.end_ns = inst->clock.now_ns();
    t.submitted_display_ns = info->displayTime;
    t.layers = info->layerCount;
    t.projection_views = projection_views;
    if (session->capture) {
      if (session->capture->wants_images(frame))
        t.views_captured = capture_frame(rt, *session, *info, frame);
      int64_t sample_time_ns = 0;
      const GazeSample g = eye_tracker_sample(*inst, session, info->displayTime, sample_time_ns);
      t.gaze_valid = g.valid && inst->config.eye_tracking;
      t.gaze_x = g.direction.x;
      t.gaze_y = g.direction.y;
      t.gaze_z = g.direction.z;
      session->capture->write_row(t);
    }
    const uint64_t budget = inst->config.frame_budget;
    if (budget != 0 && session->frames_ended >= budget && !session->exit_requested) {
      log(LogLevel::Info,
          "frame budget of " + std::to_string(budget) + " frames reached: requesting exit");
      begin_exit(*inst, *session);
    }
    return XR_SUCCESS;
  });
}

}  // namespace

void register_session_functions(FunctionTable& t) {
  add(t, "xrCreateSession", &create_session);
  add(t, "xrDestroySession", &destroy_session);
  add(t, "xrBeginSession", &begin_session);
  add(t, "xrEndSession", &end_session);
  add(t, "xrRequestExitSession", &request_exit_session);
  add(t, "xrWaitFrame", &wait_frame);
  add(t, "xrBeginFrame", &begin_frame);
  add(t, "xrEndFrame", &end_frame);
}

}  // namespace foveart::sim
