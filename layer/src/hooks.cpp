// Instance, session and frame hooks plus the extension's functions. Each is
// noexcept behind exception_barrier; state comes from the Registry and the
// lock is never held while calling down the chain.
#include "hooks.hpp"

#include <cmath>
#include <cstring>
#include <vector>

#include "barrier.hpp"
#include "log.hpp"
#include "next_chain.hpp"
#include "renderer.hpp"
#include "vulkan_device.hpp"

namespace foveart::layer {
namespace {

XRAPI_ATTR XrResult XRAPI_CALL hook_xrDestroyInstance(XrInstance instance) noexcept {
  return exception_barrier("xrDestroyInstance", [&]() -> XrResult {
    auto state = Registry::get().instance(instance);
    if (state == nullptr) return XR_ERROR_HANDLE_INVALID;
    // Renderers own runtime swapchains: release them while the instance lives.
    auto renderers = Registry::get().remove_instance(instance);
    renderers.clear();
    return state->next.DestroyInstance(instance);
  });
}

XRAPI_ATTR XrResult XRAPI_CALL hook_xrCreateSession(XrInstance instance, const XrSessionCreateInfo* info,
                                                     XrSession* out_session) noexcept {
  return exception_barrier("xrCreateSession", [&]() -> XrResult {
    auto state = Registry::get().instance(instance);
    if (state == nullptr) return XR_ERROR_HANDLE_INVALID;
    const XrResult result = state->next.CreateSession(instance, info, out_session);
    if (XR_FAILED(result) || info == nullptr || out_session == nullptr) return result;
    auto session = std::make_shared<SessionState>();
    session->handle = *out_session;
    session->system_id = info->systemId;
    session->instance = state;
    // XR_TYPE_GRAPHICS_BINDING_VULKAN2_KHR aliases XR_TYPE_GRAPHICS_BINDING_VULKAN_KHR;
    // both structs have the same layout.
    if (auto* vk = find_in_chain<XrGraphicsBindingVulkanKHR>(info->next, XR_TYPE_GRAPHICS_BINDING_VULKAN_KHR)) {
      session->has_vulkan = true;
      session->vk_instance = vk->instance;
      session->vk_instance_api_version = Registry::get().vulkan_instance_api_version(vk->instance);
      session->vk_physical_device = vk->physicalDevice;
      session->vk_device = vk->device;
      session->vk_queue_family_index = vk->queueFamilyIndex;
      session->vk_queue_index = vk->queueIndex;
      const VulkanDeviceFeatures features = Registry::get().vulkan_device(vk->device);
      session->buffer_device_address = features.buffer_device_address;
      session->timeline_semaphore = features.timeline_semaphore;
    }
    if (state->eye_gaze.ready()) {
      session->eye_gaze = std::make_shared<SessionEyeGaze>(*out_session, state->eye_gaze,
                                                           state->next.GetInstanceProcAddr, instance);
    }
    Registry::get().add_session(std::move(session));
    return result;
  });
}

XRAPI_ATTR XrResult XRAPI_CALL hook_xrDestroySession(XrSession session) noexcept {
  return exception_barrier("xrDestroySession", [&]() -> XrResult {
    auto state = Registry::get().session(session);
    if (state == nullptr) return XR_ERROR_HANDLE_INVALID;
    auto renderers = Registry::get().remove_session(session);
    renderers.clear();  // their swapchains go before the session
    return state->instance->next.DestroySession(session);
  });
}

// The action system: the layer's gaze action rides along the app's calls.
XRAPI_ATTR XrResult XRAPI_CALL hook_xrSuggestInteractionProfileBindings(
    XrInstance instance, const XrInteractionProfileSuggestedBinding* info) noexcept {
  return exception_barrier("xrSuggestInteractionProfileBindings", [&]() -> XrResult {
    auto state = Registry::get().instance(instance);
    if (state == nullptr) return XR_ERROR_HANDLE_INVALID;
    const auto& gaze = state->eye_gaze;
    if (info == nullptr || !gaze.ready() || info->interactionProfile != gaze.profile) {
      return state->next.SuggestInteractionProfileBindings(instance, info);
    }
    // The app did not enable XR_EXT_eye_gaze_interaction: to it the profile does not exist.
    if (gaze.hidden_from_app) return XR_ERROR_PATH_UNSUPPORTED;
    // Suggestions replace earlier ones per profile: keep the layer's binding in.
    std::vector<XrActionSuggestedBinding> bindings;
    if (info->suggestedBindings != nullptr) {
      bindings.assign(info->suggestedBindings, info->suggestedBindings + info->countSuggestedBindings);
    }
    bindings.push_back(XrActionSuggestedBinding{gaze.pose_action, gaze.gaze_pose});
    XrInteractionProfileSuggestedBinding merged = *info;
    merged.countSuggestedBindings = static_cast<uint32_t>(bindings.size());
    merged.suggestedBindings = bindings.data();
    return state->next.SuggestInteractionProfileBindings(instance, &merged);
  });
}

XRAPI_ATTR XrResult XRAPI_CALL hook_xrAttachSessionActionSets(XrSession session,
                                                               const XrSessionActionSetsAttachInfo* info) noexcept {
  return exception_barrier("xrAttachSessionActionSets", [&]() -> XrResult {
    auto state = Registry::get().session(session);
    if (state == nullptr) return XR_ERROR_HANDLE_INVALID;
    const auto next = state->instance->next.AttachSessionActionSets;
    if (info == nullptr || state->eye_gaze == nullptr) return next(session, info);
    bool already = false;
    const auto sets = state->eye_gaze->sets_to_attach(*info, &already);
    if (already) {
      log(LogLevel::Warn, "xrAttachSessionActionSets: the layer already attached its gaze action set (the app "
                          "attached nothing before its first foveated frame); the runtime decides");
      return next(session, info);
    }
    XrSessionActionSetsAttachInfo down = *info;
    down.countActionSets = static_cast<uint32_t>(sets.size());
    down.actionSets = sets.data();
    const XrResult result = next(session, &down);
    state->eye_gaze->app_attached(result);
    return result;
  });
}

XRAPI_ATTR XrResult XRAPI_CALL hook_xrSyncActions(XrSession session, const XrActionsSyncInfo* info) noexcept {
  return exception_barrier("xrSyncActions", [&]() -> XrResult {
    auto state = Registry::get().session(session);
    if (state == nullptr) return XR_ERROR_HANDLE_INVALID;
    const auto next = state->instance->next.SyncActions;
    if (info == nullptr || state->eye_gaze == nullptr) return next(session, info);
    const auto sets = state->eye_gaze->sets_to_sync(*info);
    XrActionsSyncInfo down = *info;
    down.countActiveActionSets = static_cast<uint32_t>(sets.size());
    down.activeActionSets = sets.empty() ? nullptr : sets.data();
    const XrResult result = next(session, &down);
    state->eye_gaze->app_synced(result);
    return result;
  });
}

XRAPI_ATTR XrResult XRAPI_CALL hook_xrGetCurrentInteractionProfile(XrSession session, XrPath top_level_user_path,
                                                                    XrInteractionProfileState* profile) noexcept {
  return exception_barrier("xrGetCurrentInteractionProfile", [&]() -> XrResult {
    auto state = Registry::get().session(session);
    if (state == nullptr) return XR_ERROR_HANDLE_INVALID;
    const auto& gaze = state->instance->eye_gaze;
    // /user/eyes_ext does not exist for an app that did not enable the extension.
    if (gaze.ready() && gaze.hidden_from_app && top_level_user_path == gaze.eyes_user) return XR_ERROR_PATH_UNSUPPORTED;
    return state->instance->next.GetCurrentInteractionProfile(session, top_level_user_path, profile);
  });
}

// Swapchains: their extents, so that an imageRect can be checked against them.
XRAPI_ATTR XrResult XRAPI_CALL hook_xrCreateSwapchain(XrSession session, const XrSwapchainCreateInfo* info,
                                                       XrSwapchain* out_swapchain) noexcept {
  return exception_barrier("xrCreateSwapchain", [&]() -> XrResult {
    auto state = Registry::get().session(session);
    if (state == nullptr) return XR_ERROR_HANDLE_INVALID;
    const XrResult result = state->instance->next.CreateSwapchain(session, info, out_swapchain);
    if (XR_SUCCEEDED(result) && info != nullptr && out_swapchain != nullptr) {
      Registry::get().add_swapchain(*out_swapchain, SwapchainExtent{session, info->width, info->height, info->arraySize});
    }
    return result;
  });
}

XRAPI_ATTR XrResult XRAPI_CALL hook_xrDestroySwapchain(XrSwapchain swapchain) noexcept {
  return exception_barrier("xrDestroySwapchain", [&]() -> XrResult {
    // Any session's next link will do: the instance's dispatch is the same for all of them.
    auto next = Registry::get().destroy_swapchain_function(swapchain);
    if (next == nullptr) return XR_ERROR_HANDLE_INVALID;
    const XrResult result = next(swapchain);
    if (XR_SUCCEEDED(result)) Registry::get().remove_swapchain(swapchain);
    return result;
  });
}

// A view's subImage lies inside a swapchain of this session: positive extent,
// offset + extent within the image (in 64 bits: no int32 wrap), a valid array layer.
bool image_rect_inside(const XrSwapchainSubImage& sub, XrSession session) {
  const auto extent = Registry::get().swapchain(sub.swapchain, session);
  if (!extent) return false;
  const XrRect2Di& r = sub.imageRect;
  if (r.offset.x < 0 || r.offset.y < 0 || r.extent.width <= 0 || r.extent.height <= 0) return false;
  return int64_t{r.offset.x} + r.extent.width <= int64_t{extent->width_px} &&
         int64_t{r.offset.y} + r.extent.height <= int64_t{extent->height_px} &&
         sub.imageArrayIndex < extent->array_size;
}

// The frame path: opted-in projection layers get their views rewritten.
XrResult end_frame(XrSession session, const XrFrameEndInfo* info) {
  auto state = Registry::get().session(session);
  if (state == nullptr) return XR_ERROR_HANDLE_INVALID;
  const PFN_xrEndFrame next_end_frame = state->instance->next.EndFrame;
  if (info == nullptr || info->layerCount == 0 || info->layers == nullptr ||
      !Registry::get().session_has_renderers(session)) {
    return next_end_frame(session, info);  // nothing opted in: untouched
  }

  // Copies are made only for layers we rewrite; the rest keep the app's pointers.
  std::vector<const XrCompositionLayerBaseHeader*> layers(info->layers, info->layers + info->layerCount);
  std::vector<XrCompositionLayerProjection> projections;
  std::vector<std::vector<XrCompositionLayerProjectionView>> views;
  ChainCopies chain_copies;  // the app's next chains minus our struct
  projections.reserve(info->layerCount);
  views.reserve(info->layerCount);
  for (uint32_t i = 0; i < info->layerCount; ++i) {
    const auto* base = info->layers[i];
    if (base == nullptr || type_of(base) != static_cast<std::int32_t>(XR_TYPE_COMPOSITION_LAYER_PROJECTION)) continue;
    const auto* projection = reinterpret_cast<const XrCompositionLayerProjection*>(base);
    const auto* opt_in = find_in_chain<XrFoveatedRayTracingLayerFOVEART>(
        projection->next, XR_TYPE_FOVEATED_RAY_TRACING_LAYER_FOVEART);
    if (opt_in == nullptr || projection->views == nullptr || projection->viewCount == 0) continue;
    std::shared_ptr<FoveatedRenderer> other;
    auto renderer = Registry::get().renderer_of_session(opt_in->renderer, session, &other);
    if (other != nullptr) other->count_foreign_session_layer();
    if (renderer == nullptr) continue;  // unknown or another session's renderer: the layer as submitted

    const auto* display = find_in_chain<XrFoveatedDisplayTransformFOVEART>(
        projection->next, XR_TYPE_FOVEATED_DISPLAY_TRANSFORM_FOVEART);
    auto& copy = projections.emplace_back(*projection);
    // Strip our structs wherever they sit, so layers below never see them; the
    // app's structs stay as submitted (the nodes before them are copied).
    const void* without_opt_in = nullptr;
    const bool stripped = chain_copies.without(projection->next, opt_in, &without_opt_in) &&
                          (display == nullptr || chain_copies.without(without_opt_in, display, &copy.next));
    if (display == nullptr) copy.next = without_opt_in;
    if (!stripped) {
      static LogOnce once;
      if (once.first()) {
        log(LogLevel::Warn, "xrEndFrame: a struct of unknown type precedes the FoveaRT structs in the "
                            "projection layer's next chain; it is forwarded as is (logged once)");
      }
    }
    auto& view_copy = views.emplace_back(projection->views, projection->views + projection->viewCount);
    std::vector<bool> rect_valid(projection->viewCount);
    for (uint32_t v = 0; v < projection->viewCount; ++v) {
      rect_valid[v] = image_rect_inside(projection->views[v].subImage, session);
    }
    try {
      renderer->render(info->displayTime, *projection, view_copy.data(), rect_valid, display);
    } catch (const std::exception& e) {
      // The frame still goes out, with the app's own views for this layer.
      static LogOnce once;
      if (once.first()) log(LogLevel::Error, "xrEndFrame: foveated renderer failed: ", e.what(), " (logged once)");
      view_copy.assign(projection->views, projection->views + projection->viewCount);
    }
    copy.views = view_copy.data();
    layers[i] = reinterpret_cast<const XrCompositionLayerBaseHeader*>(&copy);
  }
  XrFrameEndInfo down = *info;
  down.layers = layers.data();
  return next_end_frame(session, &down);
}

XRAPI_ATTR XrResult XRAPI_CALL hook_xrEndFrame(XrSession session, const XrFrameEndInfo* info) noexcept {
  return exception_barrier("xrEndFrame", [&] { return end_frame(session, info); });
}

// "" when every family is one of the session's physical device; else what is wrong.
std::string unknown_queue_family(const SessionState& session, const std::vector<uint32_t>& families) {
  uint32_t count = 0;
  if (!families.empty()) vkGetPhysicalDeviceQueueFamilyProperties(session.vk_physical_device, &count, nullptr);
  for (const uint32_t family : families)
    if (family >= count) return std::to_string(family) + " is not a queue family of the session's device";
  return "";
}

XRAPI_ATTR XrResult XRAPI_CALL hook_xrCreateFoveatedRendererFOVEART(
    XrSession session, const XrFoveatedRendererCreateInfoFOVEART* info,
    XrFoveatedRendererFOVEART* out_renderer) noexcept {
  return exception_barrier("xrCreateFoveatedRendererFOVEART", [&]() -> XrResult {
    auto state = Registry::get().session(session);
    if (state == nullptr) return XR_ERROR_HANDLE_INVALID;
    if (info == nullptr || out_renderer == nullptr || type_of(info) != static_cast<std::int32_t>(XR_TYPE_FOVEATED_RENDERER_CREATE_INFO_FOVEART)) {
      log(LogLevel::Error, "xrCreateFoveatedRendererFOVEART: createInfo missing or of the wrong type");
      return XR_ERROR_VALIDATION_FAILURE;
    }
    RendererSettings settings;
    std::string error;
    if (!resolve_settings(*info, state->instance->config, &settings, &error)) {
      log(LogLevel::Error, "xrCreateFoveatedRendererFOVEART: ", error);
      return XR_ERROR_VALIDATION_FAILURE;
    }
    if (!state->has_vulkan) {
      log(LogLevel::Error, "xrCreateFoveatedRendererFOVEART: the session has no Vulkan graphics binding "
                           "(XR_KHR_vulkan_enable2 is required)");
      return XR_ERROR_GRAPHICS_DEVICE_INVALID;
    }
    if (settings.app_trace && !state->timeline_semaphore) {
      log(LogLevel::Error, "xrCreateFoveatedRendererFOVEART: XrFoveatedAppTraceInfoFOVEART needs the session's device "
                           "made through xrCreateVulkanDeviceKHR with Vulkan 1.2's timelineSemaphore enabled");
      return XR_ERROR_VALIDATION_FAILURE;
    }
    if (const std::string bad = unknown_queue_family(*state, settings.app_queue_families); !bad.empty()) {
      log(LogLevel::Error, "xrCreateFoveatedRendererFOVEART: XrFoveatedAppTraceInfoFOVEART::queueFamilyIndices: ", bad);
      return XR_ERROR_VALIDATION_FAILURE;
    }
    auto renderer = std::make_shared<FoveatedRenderer>(state, std::move(settings));
    *out_renderer = Registry::get().add_renderer(session, std::move(renderer));
    return XR_SUCCESS;
  });
}

XRAPI_ATTR XrResult XRAPI_CALL hook_xrDestroyFoveatedRendererFOVEART(XrFoveatedRendererFOVEART renderer) noexcept {
  return exception_barrier("xrDestroyFoveatedRendererFOVEART", [&]() -> XrResult {
    auto removed = Registry::get().remove_renderer(renderer);
    return removed == nullptr ? XR_ERROR_HANDLE_INVALID : XR_SUCCESS;
  });
}

XRAPI_ATTR XrResult XRAPI_CALL hook_xrGetFoveatedRendererStatsFOVEART(XrFoveatedRendererFOVEART renderer,
                                                                       XrFoveatedRendererStatsFOVEART* stats) noexcept {
  return exception_barrier("xrGetFoveatedRendererStatsFOVEART", [&]() -> XrResult {
    auto r = Registry::get().renderer(renderer);
    if (r == nullptr) return XR_ERROR_HANDLE_INVALID;
    if (stats == nullptr || type_of(stats) != static_cast<std::int32_t>(XR_TYPE_FOVEATED_RENDERER_STATS_FOVEART)) return XR_ERROR_VALIDATION_FAILURE;
    r->stats(stats);
    return XR_SUCCESS;
  });
}

XRAPI_ATTR XrResult XRAPI_CALL hook_xrAcquireFoveatedRayBatchFOVEART(
    XrFoveatedRendererFOVEART renderer, const XrFoveatedRayBatchAcquireInfoFOVEART* info,
    XrFoveatedRayBatchFOVEART* batch) noexcept {
  return exception_barrier("xrAcquireFoveatedRayBatchFOVEART", [&]() -> XrResult {
    auto r = Registry::get().renderer(renderer);
    if (r == nullptr) return XR_ERROR_HANDLE_INVALID;
    if (info == nullptr || type_of(info) != static_cast<std::int32_t>(XR_TYPE_FOVEATED_RAY_BATCH_ACQUIRE_INFO_FOVEART) ||
        batch == nullptr || type_of(batch) != static_cast<std::int32_t>(XR_TYPE_FOVEATED_RAY_BATCH_FOVEART)) {
      log(LogLevel::Error, "xrAcquireFoveatedRayBatchFOVEART: acquireInfo or batch missing or of the wrong type");
      return XR_ERROR_VALIDATION_FAILURE;
    }
    return r->acquire_ray_batch(*info, batch);
  });
}

XRAPI_ATTR XrResult XRAPI_CALL hook_xrReleaseFoveatedRayBatchFOVEART(XrFoveatedRendererFOVEART renderer,
                                                                      uint64_t batch_id) noexcept {
  return exception_barrier("xrReleaseFoveatedRayBatchFOVEART", [&]() -> XrResult {
    auto r = Registry::get().renderer(renderer);
    if (r == nullptr) return XR_ERROR_HANDLE_INVALID;
    return r->release_ray_batch(batch_id);
  });
}

struct HookEntry {
  std::string_view name;
  PFN_xrVoidFunction function;
  bool extension;
};

template <class Fn>
PFN_xrVoidFunction as_void(Fn fn) {
  return reinterpret_cast<PFN_xrVoidFunction>(fn);
}

const HookEntry* hooks_begin(std::size_t* out_count) {
  static const HookEntry kHooks[] = {
      {"xrDestroyInstance", as_void(&hook_xrDestroyInstance), false},
      {"xrCreateSession", as_void(&hook_xrCreateSession), false},
      {"xrDestroySession", as_void(&hook_xrDestroySession), false},
      {"xrEndFrame", as_void(&hook_xrEndFrame), false},
      {"xrCreateSwapchain", as_void(&hook_xrCreateSwapchain), false},
      {"xrDestroySwapchain", as_void(&hook_xrDestroySwapchain), false},
      {"xrSuggestInteractionProfileBindings", as_void(&hook_xrSuggestInteractionProfileBindings), false},
      {"xrAttachSessionActionSets", as_void(&hook_xrAttachSessionActionSets), false},
      {"xrSyncActions", as_void(&hook_xrSyncActions), false},
      {"xrGetCurrentInteractionProfile", as_void(&hook_xrGetCurrentInteractionProfile), false},
      {"xrCreateVulkanInstanceKHR", as_void(&hook_xrCreateVulkanInstanceKHR), false},
      {"xrCreateVulkanDeviceKHR", as_void(&hook_xrCreateVulkanDeviceKHR), false},
      {"xrCreateFoveatedRendererFOVEART", as_void(&hook_xrCreateFoveatedRendererFOVEART), true},
      {"xrDestroyFoveatedRendererFOVEART", as_void(&hook_xrDestroyFoveatedRendererFOVEART), true},
      {"xrGetFoveatedRendererStatsFOVEART", as_void(&hook_xrGetFoveatedRendererStatsFOVEART), true},
      {"xrAcquireFoveatedRayBatchFOVEART", as_void(&hook_xrAcquireFoveatedRayBatchFOVEART), true},
      {"xrReleaseFoveatedRayBatchFOVEART", as_void(&hook_xrReleaseFoveatedRayBatchFOVEART), true},
  };
  *out_count = std::size(kHooks);
  return kHooks;
}

}  // namespace

PFN_xrVoidFunction find_hook(std::string_view name, const InstanceState& instance) {
  std::size_t count = 0;
  const HookEntry* hooks = hooks_begin(&count);
  for (std::size_t i = 0; i < count; ++i) {
    if (hooks[i].name != name) continue;
    if (hooks[i].extension && !instance.extension_enabled) return nullptr;
    // Another extension's function: hooked only where the next link has it.
    if (name == "xrCreateVulkanInstanceKHR" && instance.next.CreateVulkanInstanceKHR == nullptr) return nullptr;
    if (name == "xrCreateVulkanDeviceKHR" && instance.next.CreateVulkanDeviceKHR == nullptr) return nullptr;
    return hooks[i].function;
  }
  return nullptr;
}

bool is_extension_function(std::string_view name) {
  std::size_t count = 0;
  const HookEntry* hooks = hooks_begin(&count);
  for (std::size_t i = 0; i < count; ++i) {
    if (hooks[i].name == name) return hooks[i].extension;
  }
  return false;
}

}  // namespace foveart::layer
