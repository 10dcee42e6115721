// xrCreateVulkanDeviceKHR (XR_KHR_vulkan_enable2) passed down, with what the
// app enabled on its VkDevice recorded in the Registry: xrCreateSession copies
// it into the SessionState of a session on that device. A device the app made
// without this call (XR_KHR_vulkan_enable) records nothing: no features.
#pragma once

#include "state.hpp"

namespace foveart::layer {

// The features the layer's device work can use that `info` enables, from
// VkPhysicalDeviceVulkan12Features, VkPhysicalDeviceBufferDeviceAddressFeatures
// or VkPhysicalDeviceTimelineSemaphoreFeatures in its pNext chain.
VulkanDeviceFeatures enabled_device_features(const VkDeviceCreateInfo* info);

XRAPI_ATTR XrResult XRAPI_CALL hook_xrCreateVulkanDeviceKHR(XrInstance instance,
                                                             const XrVulkanDeviceCreateInfoKHR* info,
                                                             VkDevice* vulkan_device, VkResult* vulkan_result) noexcept;

}  // namespace foveart::layer
