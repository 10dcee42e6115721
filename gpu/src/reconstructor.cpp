#include "gpu/reconstructor.hpp"

#include <vector>

namespace foveart::gpu {

std::string unsupported_reason(const Device& device) {
  const VkPhysicalDevice physical_device = device.physical_device;
  const uint32_t queue_family_index = device.queue_family_index;
  uint32_t count = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(physical_device, &count, nullptr);
  std::vector<VkQueueFamilyProperties> families(count);
  vkGetPhysicalDeviceQueueFamilyProperties(physical_device, &count, families.data());
  if (queue_family_index >= count) return "the session's queue family does not exist";
  if ((families[queue_family_index].queueFlags & VK_QUEUE_COMPUTE_BIT) == 0) {
    return "the session's queue family has no compute";
  }
  VkPhysicalDeviceFeatures features{};
  vkGetPhysicalDeviceFeatures(physical_device, &features);
  if (!features.shaderStorageBufferArrayDynamicIndexing) {
    return "the device lacks shaderStorageBufferArrayDynamicIndexing (table chunks)";
  }
  VkPhysicalDeviceProperties properties{};
  vkGetPhysicalDeviceProperties(physical_device, &properties);
  if (VK_API_VERSION_MINOR(properties.apiVersion) < 1 && VK_API_VERSION_MAJOR(properties.apiVersion) == 1) {
    return "the device is Vulkan 1.0; the shaders are SPIR-V 1.3 (Vulkan 1.1)";
  }
  // The app's instance caps the version its devices are used at (Vulkan spec, VkApplicationInfo).
  if (device.instance_api_version != 0 && device.instance_api_version < VK_API_VERSION_1_1) {
    return "the app's Vulkan instance asked for Vulkan 1.0 (VkApplicationInfo::apiVersion); the shaders are SPIR-V "
           "1.3 (Vulkan 1.1)";
  }
  if (properties.limits.maxPerStageDescriptorStorageBuffers < kFrameStorageBuffers) {
    return "the device binds fewer than " + std::to_string(kFrameStorageBuffers) + " storage buffers per stage";
  }
  return {};
}

std::unique_ptr<Reconstructor> Reconstructor::create(const Device& device, std::string* error) {
  if (std::string why = unsupported_reason(device); !why.empty()) {
    return *error = why, nullptr;
  }
  std::unique_ptr<Reconstructor> r(new Reconstructor());
  r->context_ = Context::create(device, error);
  if (r->context_ == nullptr) return nullptr;
  r->pipelines_ = FramePipelines::create(device.device, error);
  if (r->pipelines_ == nullptr) return nullptr;
  return r;
}

}  // namespace foveart::gpu
