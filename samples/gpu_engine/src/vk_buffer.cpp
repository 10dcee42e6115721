// vkCreateBuffer -> vkAllocateMemory (host-visible, coherent) -> bind -> map.
#include "vk_buffer.hpp"

#include <algorithm>
#include <cstdint>
#include <cstring>

namespace foveart::gpu_engine {
namespace {

// The first memory type allowed by `bits` with all of `flags`; UINT32_MAX if none.
uint32_t find_memory_type(VkPhysicalDevice physical_device, uint32_t bits, VkMemoryPropertyFlags flags) {
  VkPhysicalDeviceMemoryProperties props{};
  vkGetPhysicalDeviceMemoryProperties(physical_device, &props);
  for (uint32_t i = 0; i < props.memoryTypeCount; ++i)
    if ((bits & (1u << i)) != 0 && (props.memoryTypes[i].propertyFlags & flags) == flags) return i;
  return UINT32_MAX;
}

}  // namespace

bool MappedBuffer::create(VkPhysicalDevice physical_device, VkDevice device, VkDeviceSize bytes, const void* data,
                          std::string* error, VkBufferUsageFlags usage) {
  destroy();
  device_ = device;
  size_ = std::max<VkDeviceSize>(bytes, 16);
  VkBufferCreateInfo info{};
  info.sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO;
  info.size = size_;
  info.usage = usage;
  info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  VkResult r = vkCreateBuffer(device, &info, nullptr, &buffer_);
  if (r != VK_SUCCESS) {
    if (error) *error = "gpu_engine: vkCreateBuffer failed (" + std::to_string(static_cast<int>(r)) + ")";
    return false;
  }
  VkMemoryRequirements req{};
  vkGetBufferMemoryRequirements(device, buffer_, &req);
  constexpr VkMemoryPropertyFlags kHost = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
  uint32_t type = find_memory_type(physical_device, req.memoryTypeBits, kHost | VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
  VkMemoryAllocateInfo alloc{};
  alloc.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO;
  alloc.allocationSize = req.size;
  VkMemoryAllocateFlagsInfo flags{};
  flags.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_FLAGS_INFO;
  flags.flags = VK_MEMORY_ALLOCATE_DEVICE_ADDRESS_BIT;
  if ((usage & VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT) != 0) alloc.pNext = &flags;
  r = VK_ERROR_OUT_OF_DEVICE_MEMORY;
  if (type != UINT32_MAX) {  // device-local host-visible heaps can be small: fall back below
    alloc.memoryTypeIndex = type;
    r = vkAllocateMemory(device, &alloc, nullptr, &memory_);
  }
  if (r != VK_SUCCESS) {
    type = find_memory_type(physical_device, req.memoryTypeBits, kHost);
    if (type == UINT32_MAX) {
      if (error) *error = "gpu_engine: no host-visible coherent memory type for a storage buffer";
      destroy();
      return false;
    }
    alloc.memoryTypeIndex = type;
    r = vkAllocateMemory(device, &alloc, nullptr, &memory_);
  }
  if (r == VK_SUCCESS) r = vkBindBufferMemory(device, buffer_, memory_, 0);
  if (r == VK_SUCCESS) r = vkMapMemory(device, memory_, 0, VK_WHOLE_SIZE, 0, &mapped_);
  if (r != VK_SUCCESS) {
    if (error) *error = "gpu_engine: allocating " + std::to_string(size_) + " bytes failed (" +
                        std::to_string(static_cast<int>(r)) + ")";
    destroy();
    return false;
  }
  std::memset(mapped_, 0, static_cast<size_t>(size_));
  if (data != nullptr && bytes > 0) std::memcpy(mapped_, data, static_cast<size_t>(bytes));
  return true;
}

void MappedBuffer::destroy() {
  if (device_ == VK_NULL_HANDLE) return;
  if (buffer_ != VK_NULL_HANDLE) vkDestroyBuffer(device_, buffer_, nullptr);
  if (memory_ != VK_NULL_HANDLE) vkFreeMemory(device_, memory_, nullptr);  // unmaps implicitly
  buffer_ = VK_NULL_HANDLE;
  memory_ = VK_NULL_HANDLE;
  mapped_ = nullptr;
  size_ = 0;
}

}  // namespace foveart::gpu_engine
