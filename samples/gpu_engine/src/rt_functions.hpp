// The device-level entry points of VK_KHR_acceleration_structure,
// VK_KHR_ray_tracing_pipeline and VK_KHR_buffer_device_address, loaded with
// vkGetDeviceProcAddr (the loader exports none of them).
//
// Lifetime:  valid while the VkDevice lives. Threads: read-only after load().
// Errors:    load() returns false with *error naming the first missing function.
#pragma once

#include <vulkan/vulkan.h>

#include <string>

namespace foveart::gpu_engine {

struct RtFunctions {
  PFN_vkGetBufferDeviceAddressKHR get_buffer_device_address = nullptr;
  PFN_vkCreateAccelerationStructureKHR create_acceleration_structure = nullptr;
  PFN_vkDestroyAccelerationStructureKHR destroy_acceleration_structure = nullptr;
  PFN_vkGetAccelerationStructureBuildSizesKHR get_acceleration_structure_build_sizes = nullptr;
  PFN_vkGetAccelerationStructureDeviceAddressKHR get_acceleration_structure_device_address = nullptr;
  PFN_vkCmdBuildAccelerationStructuresKHR cmd_build_acceleration_structures = nullptr;
  PFN_vkCreateRayTracingPipelinesKHR create_ray_tracing_pipelines = nullptr;
  PFN_vkGetRayTracingShaderGroupHandlesKHR get_ray_tracing_shader_group_handles = nullptr;
  PFN_vkCmdTraceRaysKHR cmd_trace_rays = nullptr;
  PFN_vkCmdTraceRaysIndirectKHR cmd_trace_rays_indirect = nullptr;  // optional: null where not loaded

  [[nodiscard]] bool load(VkDevice device, std::string* error);
  VkDeviceAddress address(VkDevice device, VkBuffer buffer) const;
};

}  // namespace foveart::gpu_engine
