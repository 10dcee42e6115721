// What a Vulkan device needs for GpuTracer's ray-tracing-pipeline backend, and
// enabling it: VK_KHR_ray_tracing_pipeline, VK_KHR_acceleration_structure and
// the extensions they require on a Vulkan 1.1 device (buffer device address,
// deferred host operations, descriptor indexing, SPIR-V 1.4, float controls),
// with the features rayTracingPipeline, accelerationStructure and bufferDeviceAddress.
//
// A VkDevice cannot be asked which extensions it was created with: whoever
// creates the device enables them here (when offered) and tells the tracer
// through GpuContext::ray_tracing_enabled.
//
// Lifetime:  enable() chains feature structs owned by this object into the
//            VkDeviceCreateInfo: keep it alive until vkCreateDevice returns.
// Threads:   none shared; one object per device creation.
// Errors:    nothing throws; missing() names what the device lacks.
#pragma once

#include <vulkan/vulkan.h>

#include <string>
#include <vector>

namespace foveart::gpu_engine {

class RayTracingDeviceSupport {
 public:
  // Queries the extensions and features `physical_device` offers (instance at
  // Vulkan 1.1 or later: vkGetPhysicalDeviceFeatures2).
  explicit RayTracingDeviceSupport(VkPhysicalDevice physical_device);
  RayTracingDeviceSupport(const RayTracingDeviceSupport&) = delete;
  RayTracingDeviceSupport& operator=(const RayTracingDeviceSupport&) = delete;

  // Every extension and feature is offered.
  bool offered() const { return missing_.empty(); }
  // The first extension or feature the device lacks ("" when offered()).
  const std::string& missing() const { return missing_; }

  // When offered(): appends the extensions to *extensions (which must already
  // hold the caller's own device extensions: info's list is replaced by it),
  // points info->ppEnabledExtensionNames at it and chains the three feature
  // structs in front of info->pNext; *extensions must outlive vkCreateDevice
  // too. Where the caller chained a VkPhysicalDeviceVulkan12Features (a
  // Vulkan 1.2 device), bufferDeviceAddress is set there instead and only the
  // two ray-tracing structs are chained: one chain may not hold both. Returns
  // offered(); changes nothing otherwise.
  bool enable(VkDeviceCreateInfo* info, std::vector<const char*>* extensions);

  // The device offers rayTracingPipelineTraceRaysIndirect, which enable() then enables too
  // (GpuContext::trace_rays_indirect: the tracer launches only the frame's rays).
  bool trace_rays_indirect() const { return offered() && indirect_; }

  // The feature chain enable() puts in front of info->pNext: pipeline -> acceleration
  // (-> address unless the chain holds a VkPhysicalDeviceVulkan12Features, whose
  // bufferDeviceAddress is set instead) -> the caller's chain. The structs must outlive
  // vkCreateDevice.
  static void chain_features(VkDeviceCreateInfo* info, VkPhysicalDeviceBufferDeviceAddressFeaturesKHR* address,
                             VkPhysicalDeviceAccelerationStructureFeaturesKHR* acceleration,
                             VkPhysicalDeviceRayTracingPipelineFeaturesKHR* pipeline);

  // The device extensions enable() adds.
  static const std::vector<const char*>& extensions();

 private:
  std::string missing_;
  bool indirect_ = false;
  VkPhysicalDeviceBufferDeviceAddressFeaturesKHR address_{};
  VkPhysicalDeviceAccelerationStructureFeaturesKHR acceleration_{};
  VkPhysicalDeviceRayTracingPipelineFeaturesKHR pipeline_{};
};

}  // namespace foveart::gpu_engine
