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

}  // namespace foveart::layer
