#include "vk_util.hpp"

namespace foveart::layer {

bool create_bound_buffer(VkDevice device, const VkPhysicalDeviceMemoryProperties& memory_properties, VkDeviceSize size,
                         VkBufferUsageFlags usage, VkMemoryPropertyFlags wanted, VkBuffer* buffer,
                         VkDeviceMemory* memory, void** mapped, std::string* error) {
  auto info = vk_struct<VkBufferCreateInfo>(VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO);
  info.size = size;
  info.usage = usage;
  info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  VkResult r = vkCreateBuffer(device, &info, nullptr, buffer);
  if (r != VK_SUCCESS) return *error = vk_error("vkCreateBuffer", r), false;
  VkMemoryRequirements req{};
  vkGetBufferMemoryRequirements(device, *buffer, &req);
  uint32_t type = UINT32_MAX;
  for (uint32_t i = 0; i < memory_properties.memoryTypeCount && type == UINT32_MAX; ++i) {
    if ((req.memoryTypeBits & (1u << i)) && (memory_properties.memoryTypes[i].propertyFlags & wanted) == wanted) type = i;
  }
  if (type == UINT32_MAX) {
    const bool host = (wanted & VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT) != 0;
    return *error = std::string("no ") + (host ? "host-visible coherent" : "device-local") + " memory type", false;
  }
  auto alloc = vk_struct<VkMemoryAllocateInfo>(VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO);
  alloc.allocationSize = req.size;
  alloc.memoryTypeIndex = type;
  r = vkAllocateMemory(device, &alloc, nullptr, memory);
  if (r != VK_SUCCESS) return *error = vk_error("vkAllocateMemory", r), false;
  r = vkBindBufferMemory(device, *buffer, *memory, 0);
  if (r != VK_SUCCESS) return *error = vk_error("vkBindBufferMemory", r), false;
  if (mapped != nullptr) {
    r = vkMapMemory(device, *memory, 0, VK_WHOLE_SIZE, 0, mapped);
    if (r != VK_SUCCESS) return *error = vk_error("vkMapMemory", r), false;
  }
  return true;
}

void memory_barrier(VkCommandBuffer cb, VkPipelineStageFlags src, VkAccessFlags src_access, VkPipelineStageFlags dst,
                    VkAccessFlags dst_access) {
  auto b = vk_struct<VkMemoryBarrier>(VK_STRUCTURE_TYPE_MEMORY_BARRIER);
  b.srcAccessMask = src_access;
  b.dstAccessMask = dst_access;
  vkCmdPipelineBarrier(cb, src, dst, 0, 1, &b, 0, nullptr, 0, nullptr);
}

bool create_compute_pipeline(VkDevice device, VkPipelineLayout layout, const uint32_t* code, size_t bytes,
                             VkPipeline* pipeline, std::string* error) {
  auto module_info = vk_struct<VkShaderModuleCreateInfo>(VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO);
  module_info.codeSize = bytes;
  module_info.pCode = code;
  VkShaderModule module = VK_NULL_HANDLE;
  VkResult r = vkCreateShaderModule(device, &module_info, nullptr, &module);
  if (r != VK_SUCCESS) return *error = vk_error("vkCreateShaderModule", r), false;
  auto info = vk_struct<VkComputePipelineCreateInfo>(VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO);
  info.stage = vk_struct<VkPipelineShaderStageCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO);
  info.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
  info.stage.module = module;
  info.stage.pName = "main";
  info.layout = layout;
  r = vkCreateComputePipelines(device, VK_NULL_HANDLE, 1, &info, nullptr, pipeline);
  vkDestroyShaderModule(device, module, nullptr);
  if (r != VK_SUCCESS) return *error = vk_error("vkCreateComputePipelines", r), false;
  return true;
}

}  // namespace foveart::layer
