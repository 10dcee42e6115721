// RtFunctions: vkGetDeviceProcAddr for each entry point the ray-tracing backend calls.
#include "rt_functions.hpp"

namespace foveart::gpu_engine {
namespace {

template <typename Pfn>
bool load_one(VkDevice device, const char* name, Pfn* out, std::string* error) {
  *out = reinterpret_cast<Pfn>(vkGetDeviceProcAddr(device, name));
  if (*out != nullptr) return true;
  if (error) *error = std::string("gpu_engine: the device has no ") + name + " (ray-tracing extensions not enabled?)";
  return false;
}

}  // namespace

bool RtFunctions::load(VkDevice device, std::string* error) {
  cmd_trace_rays_indirect =
      reinterpret_cast<PFN_vkCmdTraceRaysIndirectKHR>(vkGetDeviceProcAddr(device, "vkCmdTraceRaysIndirectKHR"));
  return load_one(device, "vkGetBufferDeviceAddressKHR", &get_buffer_device_address, error) &&
         load_one(device, "vkCreateAccelerationStructureKHR", &create_acceleration_structure, error) &&
         load_one(device, "vkDestroyAccelerationStructureKHR", &destroy_acceleration_structure, error) &&
         load_one(device, "vkGetAccelerationStructureBuildSizesKHR", &get_acceleration_structure_build_sizes, error) &&
         load_one(device, "vkGetAccelerationStructureDeviceAddressKHR", &get_acceleration_structure_device_address,
                  error) &&
         load_one(device, "vkCmdBuildAccelerationStructuresKHR", &cmd_build_acceleration_structures, error) &&
         load_one(device, "vkCreateRayTracingPipelinesKHR", &create_ray_tracing_pipelines, error) &&
         load_one(device, "vkGetRayTracingShaderGroupHandlesKHR", &get_ray_tracing_shader_group_handles, error) &&
         load_one(device, "vkCmdTraceRaysKHR", &cmd_trace_rays, error);
}

VkDeviceAddress RtFunctions::address(VkDevice device, VkBuffer buffer) const {
  VkBufferDeviceAddressInfo info{};
  info.sType = VK_STRUCTURE_TYPE_BUFFER_DEVICE_ADDRESS_INFO;
  info.buffer = buffer;
  return get_buffer_device_address(device, &info);
}

}  // namespace foveart::gpu_engine
