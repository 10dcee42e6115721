// The functions of the next link in the chain (next layer or runtime), per
// XrInstance. Filled once at xrCreateApiLayerInstance through the next
// xrGetInstanceProcAddr; optional extension functions stay null when absent.
#pragma once

#ifndef XR_USE_GRAPHICS_API_VULKAN
#define XR_USE_GRAPHICS_API_VULKAN
#endif
#include <vulkan/vulkan.h>
#include <openxr/openxr.h>
#include <openxr/openxr_platform.h>

namespace foveart::layer {

struct NextDispatch {
  PFN_xrGetInstanceProcAddr GetInstanceProcAddr = nullptr;
  PFN_xrDestroyInstance DestroyInstance = nullptr;
  PFN_xrCreateSession CreateSession = nullptr;
  PFN_xrDestroySession DestroySession = nullptr;
  PFN_xrEndFrame EndFrame = nullptr;
  PFN_xrEnumerateSwapchainFormats EnumerateSwapchainFormats = nullptr;
  PFN_xrCreateSwapchain CreateSwapchain = nullptr;
  PFN_xrDestroySwapchain DestroySwapchain = nullptr;
  PFN_xrEnumerateSwapchainImages EnumerateSwapchainImages = nullptr;
  PFN_xrAcquireSwapchainImage AcquireSwapchainImage = nullptr;
  PFN_xrWaitSwapchainImage WaitSwapchainImage = nullptr;
  PFN_xrReleaseSwapchainImage ReleaseSwapchainImage = nullptr;
  PFN_xrLocateSpace LocateSpace = nullptr;
  PFN_xrGetSystemProperties GetSystemProperties = nullptr;
  // The action system (the eye gaze source rides along the app's calls).
  PFN_xrSuggestInteractionProfileBindings SuggestInteractionProfileBindings = nullptr;
  PFN_xrAttachSessionActionSets AttachSessionActionSets = nullptr;
  PFN_xrSyncActions SyncActions = nullptr;
  PFN_xrGetCurrentInteractionProfile GetCurrentInteractionProfile = nullptr;
  // XR_KHR_vulkan_enable2, when the app enabled it (null otherwise).
  PFN_xrCreateVulkanInstanceKHR CreateVulkanInstanceKHR = nullptr;
  PFN_xrCreateVulkanDeviceKHR CreateVulkanDeviceKHR = nullptr;
};

// Loads every entry above from next_gipa; false if a core function is missing.
bool load_next_dispatch(XrInstance instance, PFN_xrGetInstanceProcAddr next_gipa, NextDispatch* out);

}  // namespace foveart::layer
