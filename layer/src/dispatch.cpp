#include "dispatch.hpp"

namespace foveart::layer {
namespace {

template <class Fn>
bool load(XrInstance instance, PFN_xrGetInstanceProcAddr gipa, const char* name, Fn* out) {
  PFN_xrVoidFunction fn = nullptr;
  if (XR_FAILED(gipa(instance, name, &fn)) || fn == nullptr) return false;
  *out = reinterpret_cast<Fn>(fn);
  return true;
}

}  // namespace

bool load_next_dispatch(XrInstance instance, PFN_xrGetInstanceProcAddr next_gipa, NextDispatch* out) {
  NextDispatch d;
  d.GetInstanceProcAddr = next_gipa;
  bool ok = true;
  ok = load(instance, next_gipa, "xrDestroyInstance", &d.DestroyInstance) && ok;
  ok = load(instance, next_gipa, "xrCreateSession", &d.CreateSession) && ok;
  ok = load(instance, next_gipa, "xrDestroySession", &d.DestroySession) && ok;
  ok = load(instance, next_gipa, "xrEndFrame", &d.EndFrame) && ok;
  ok = load(instance, next_gipa, "xrEnumerateSwapchainFormats", &d.EnumerateSwapchainFormats) && ok;
  ok = load(instance, next_gipa, "xrCreateSwapchain", &d.CreateSwapchain) && ok;
  ok = load(instance, next_gipa, "xrDestroySwapchain", &d.DestroySwapchain) && ok;
  ok = load(instance, next_gipa, "xrEnumerateSwapchainImages", &d.EnumerateSwapchainImages) && ok;
  ok = load(instance, next_gipa, "xrAcquireSwapchainImage", &d.AcquireSwapchainImage) && ok;
  ok = load(instance, next_gipa, "xrWaitSwapchainImage", &d.WaitSwapchainImage) && ok;
  ok = load(instance, next_gipa, "xrReleaseSwapchainImage", &d.ReleaseSwapchainImage) && ok;
  ok = load(instance, next_gipa, "xrLocateSpace", &d.LocateSpace) && ok;
  ok = load(instance, next_gipa, "xrGetSystemProperties", &d.GetSystemProperties) && ok;
  ok = load(instance, next_gipa, "xrSuggestInteractionProfileBindings", &d.SuggestInteractionProfileBindings) && ok;
  ok = load(instance, next_gipa, "xrAttachSessionActionSets", &d.AttachSessionActionSets) && ok;
  ok = load(instance, next_gipa, "xrSyncActions", &d.SyncActions) && ok;
  ok = load(instance, next_gipa, "xrGetCurrentInteractionProfile", &d.GetCurrentInteractionProfile) && ok;
  load(instance, next_gipa, "xrCreateVulkanInstanceKHR", &d.CreateVulkanInstanceKHR);  // optional
  load(instance, next_gipa, "xrCreateVulkanDeviceKHR", &d.CreateVulkanDeviceKHR);      // optional
  *out = d;
  return ok;
}

}  // namespace foveart::layer
