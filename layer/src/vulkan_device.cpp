#include "vulkan_device.hpp"

#include "barrier.hpp"

namespace foveart::layer {

VulkanDeviceFeatures enabled_device_features(const VkDeviceCreateInfo* info) {
  VulkanDeviceFeatures features;
  if (info == nullptr) return features;
  for (auto* s = static_cast<const VkBaseInStructure*>(info->pNext); s != nullptr; s = s->pNext) {
    if (s->sType == VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES) {
      const auto* v12 = reinterpret_cast<const VkPhysicalDeviceVulkan12Features*>(s);
      features.buffer_device_address |= v12->bufferDeviceAddress == VK_TRUE;
      features.timeline_semaphore |= v12->timelineSemaphore == VK_TRUE;
    } else if (s->sType == VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_BUFFER_DEVICE_ADDRESS_FEATURES) {
      features.buffer_device_address |=
          reinterpret_cast<const VkPhysicalDeviceBufferDeviceAddressFeatures*>(s)->bufferDeviceAddress == VK_TRUE;
    } else if (s->sType == VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_TIMELINE_SEMAPHORE_FEATURES) {
      features.timeline_semaphore |=
          reinterpret_cast<const VkPhysicalDeviceTimelineSemaphoreFeatures*>(s)->timelineSemaphore == VK_TRUE;
    }
  }
  return features;
}

XRAPI_ATTR XrResult XRAPI_CALL hook_xrCreateVulkanInstanceKHR(XrInstance instance,
                                                               const XrVulkanInstanceCreateInfoKHR* info,
                                                               VkInstance* vulkan_instance,
                                                               VkResult* vulkan_result) noexcept {
  return exception_barrier("xrCreateVulkanInstanceKHR", [&]() -> XrResult {
    auto state = Registry::get().instance(instance);
    if (state == nullptr) return XR_ERROR_HANDLE_INVALID;
    if (state->next.CreateVulkanInstanceKHR == nullptr) return XR_ERROR_FUNCTION_UNSUPPORTED;
    const XrResult result = state->next.CreateVulkanInstanceKHR(instance, info, vulkan_instance, vulkan_result);
    if (XR_SUCCEEDED(result) && info != nullptr && info->vulkanCreateInfo != nullptr && vulkan_instance != nullptr &&
        *vulkan_instance != VK_NULL_HANDLE && (vulkan_result == nullptr || *vulkan_result == VK_SUCCESS)) {
      // No application info, or an apiVersion of 0, means Vulkan 1.0 (VkApplicationInfo).
      const VkApplicationInfo* app = info->vulkanCreateInfo->pApplicationInfo;
      const uint32_t api_version = app != nullptr && app->apiVersion != 0 ? app->apiVersion : VK_API_VERSION_1_0;
      Registry::get().add_vulkan_instance(instance, *vulkan_instance, api_version);
    }
    return result;
  });
}

XRAPI_ATTR XrResult XRAPI_CALL hook_xrCreateVulkanDeviceKHR(XrInstance instance,
                                                             const XrVulkanDeviceCreateInfoKHR* info,
                                                             VkDevice* vulkan_device, VkResult* vulkan_result) noexcept {
  return exception_barrier("xrCreateVulkanDeviceKHR", [&]() -> XrResult {
    auto state = Registry::get().instance(instance);
    if (state == nullptr) return XR_ERROR_HANDLE_INVALID;
    if (state->next.CreateVulkanDeviceKHR == nullptr) return XR_ERROR_FUNCTION_UNSUPPORTED;
    const XrResult result = state->next.CreateVulkanDeviceKHR(instance, info, vulkan_device, vulkan_result);
    if (XR_SUCCEEDED(result) && info != nullptr && vulkan_device != nullptr && *vulkan_device != VK_NULL_HANDLE &&
        (vulkan_result == nullptr || *vulkan_result == VK_SUCCESS)) {
      Registry::get().add_vulkan_device(instance, *vulkan_device, enabled_device_features(info->vulkanCreateInfo));
    }
    return result;
  });
}

}  // namespace foveart::layer
