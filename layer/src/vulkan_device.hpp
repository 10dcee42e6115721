// xrCreateVulkanInstanceKHR and xrCreateVulkanDeviceKHR (XR_KHR_vulkan_enable2)
// passed down, with the Vulkan version the app's VkInstance asked for and what
// it enabled on its VkDevice recorded in the Registry: xrCreateSession copies
// them into the SessionState of a session on them. An instance or device the
// app made without these calls (XR_KHR_vulkan_enable) records nothing.
#pragma once

#include "state.hpp"

namespace foveart::layer {

// The features the layer's device work can use that `info` enables, from
// VkPhysicalDeviceVulkan12Features, VkPhysicalDeviceBufferDeviceAddressFeatures
// or VkPhysicalDeviceTimelineSemaphoreFeatures in its pNext chain.
VulkanDeviceFeatures enabled_device_features(const VkDeviceCreateInfo* info);

XRAPI_ATTR XrResult XRAPI_CALL hook_xrCreateVulkanInstanceKHR(XrInstance instance,
                                                               const XrVulkanInstanceCreateInfoKHR* info,
                                                               VkInstance* vulkan_instance,
                                                               VkResult* vulkan_result) noexcept;

XRAPI_ATTR XrResult XRAPI_CALL hook_xrCreateVulkanDeviceKHR(XrInstance instance,
                                                             const XrVulkanDeviceCreateInfoKHR* info,
                                                             VkDevice* vulkan_device, VkResult* vulkan_result) noexcept;

}  // namespace foveart::layer
