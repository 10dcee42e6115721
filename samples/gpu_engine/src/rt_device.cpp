// RayTracingDeviceSupport: vkEnumerateDeviceExtensionProperties and
// vkGetPhysicalDeviceFeatures2 for the ray-tracing-pipeline backend's needs.
#include <gpu_engine/rt_device.hpp>

#include <algorithm>
#include <cstring>

namespace foveart::gpu_engine {
namespace {

// The VkPhysicalDeviceVulkan12Features in info's chain, or null.
VkPhysicalDeviceVulkan12Features* find_vulkan12_features(const VkDeviceCreateInfo* info) {
  for (auto* s = static_cast<const VkBaseInStructure*>(info->pNext); s != nullptr; s = s->pNext) {
    if (s->sType == VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES) {
      // The caller's own struct, chained for this device creation: enable() may set its fields.
      return reinterpret_cast<VkPhysicalDeviceVulkan12Features*>(const_cast<VkBaseInStructure*>(s));
    }
  }
  return nullptr;
}

}  // namespace

const std::vector<const char*>& RayTracingDeviceSupport::extensions() {
  static const std::vector<const char*> names = {
      VK_KHR_RAY_TRACING_PIPELINE_EXTENSION_NAME,   VK_KHR_ACCELERATION_STRUCTURE_EXTENSION_NAME,
      VK_KHR_BUFFER_DEVICE_ADDRESS_EXTENSION_NAME,  VK_KHR_DEFERRED_HOST_OPERATIONS_EXTENSION_NAME,
      VK_EXT_DESCRIPTOR_INDEXING_EXTENSION_NAME,    VK_KHR_SPIRV_1_4_EXTENSION_NAME,
      VK_KHR_SHADER_FLOAT_CONTROLS_EXTENSION_NAME};
  return names;
}

RayTracingDeviceSupport::RayTracingDeviceSupport(VkPhysicalDevice physical_device) {
  if (physical_device == VK_NULL_HANDLE) {
    missing_ = "a Vulkan device";
    return;
  }
  uint32_t count = 0;
  std::vector<VkExtensionProperties> offered;
  if (vkEnumerateDeviceExtensionProperties(physical_device, nullptr, &count, nullptr) == VK_SUCCESS) {
    offered.resize(count);
    if (vkEnumerateDeviceExtensionProperties(physical_device, nullptr, &count, offered.data()) != VK_SUCCESS)
      offered.clear();
    offered.resize(std::min<size_t>(offered.size(), count));
  }
  for (const char* name : extensions()) {
    const bool has = std::any_of(offered.begin(), offered.end(),
                                 [&](const VkExtensionProperties& e) { return std::strcmp(e.extensionName, name) == 0; });
    if (!has) {
      missing_ = name;
      return;
    }
  }
  address_.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_BUFFER_DEVICE_ADDRESS_FEATURES_KHR;
  acceleration_.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ACCELERATION_STRUCTURE_FEATURES_KHR;
  pipeline_.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_RAY_TRACING_PIPELINE_FEATURES_KHR;
  acceleration_.pNext = &address_;
  pipeline_.pNext = &acceleration_;
  VkPhysicalDeviceFeatures2 features{};
  features.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2;
  features.pNext = &pipeline_;
  vkGetPhysicalDeviceFeatures2(physical_device, &features);
  if (!pipeline_.rayTracingPipeline) missing_ = "the rayTracingPipeline feature";
  else if (!acceleration_.accelerationStructure) missing_ = "the accelerationStructure feature";
  else if (!address_.bufferDeviceAddress) missing_ = "the bufferDeviceAddress feature";
  indirect_ = pipeline_.rayTracingPipelineTraceRaysIndirect == VK_TRUE;
}

void RayTracingDeviceSupport::chain_features(VkDeviceCreateInfo* info,
                                             VkPhysicalDeviceBufferDeviceAddressFeaturesKHR* address,
                                             VkPhysicalDeviceAccelerationStructureFeaturesKHR* acceleration,
                                             VkPhysicalDeviceRayTracingPipelineFeaturesKHR* pipeline) {
  // A VkPhysicalDeviceVulkan12Features of the caller's must carry the feature instead: the
  // spec forbids it beside a VkPhysicalDeviceBufferDeviceAddressFeatures in one chain.
  if (auto* v12 = find_vulkan12_features(info)) {
    v12->bufferDeviceAddress = VK_TRUE;
    acceleration->pNext = const_cast<void*>(info->pNext);
  } else {
    address->pNext = const_cast<void*>(info->pNext);
    acceleration->pNext = address;
  }
  pipeline->pNext = acceleration;
  info->pNext = pipeline;
}

bool RayTracingDeviceSupport::enable(VkDeviceCreateInfo* info, std::vector<const char*>* extension_names) {
  if (!offered() || info == nullptr || extension_names == nullptr) return false;
  // Only what the tracer uses: no capture/replay, indirect builds or host commands.
  VkPhysicalDeviceBufferDeviceAddressFeaturesKHR address{};
  address.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_BUFFER_DEVICE_ADDRESS_FEATURES_KHR;
  address.bufferDeviceAddress = VK_TRUE;
  VkPhysicalDeviceAccelerationStructureFeaturesKHR acceleration{};
  acceleration.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ACCELERATION_STRUCTURE_FEATURES_KHR;
  acceleration.accelerationStructure = VK_TRUE;
  VkPhysicalDeviceRayTracingPipelineFeaturesKHR pipeline{};
  pipeline.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_RAY_TRACING_PIPELINE_FEATURES_KHR;
  pipeline.rayTracingPipeline = VK_TRUE;
  pipeline.rayTracingPipelineTraceRaysIndirect = indirect_ ? VK_TRUE : VK_FALSE;
  address_ = address;
  acceleration_ = acceleration;
  pipeline_ = pipeline;
  chain_features(info, &address_, &acceleration_, &pipeline_);
  for (const char* name : extensions())
    if (std::none_of(extension_names->begin(), extension_names->end(),
                     [&](const char* e) { return std::strcmp(e, name) == 0; }))
      extension_names->push_back(name);
  info->enabledExtensionCount = static_cast<uint32_t>(extension_names->size());
  info->ppEnabledExtensionNames = extension_names->data();
  return true;
}

}  // namespace foveart::gpu_engine
