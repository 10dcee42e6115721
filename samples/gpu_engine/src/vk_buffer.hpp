// A storage buffer in host-visible, coherent memory (device-local too where the
// device offers such a type), mapped for its whole life. With
// VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT in `usage` its memory is allocated
// with VK_MEMORY_ALLOCATE_DEVICE_ADDRESS_BIT (the ray-tracing backend's buffers).
#pragma once

#include <vulkan/vulkan.h>

#include <cstddef>
#include <string>

namespace foveart::gpu_engine {

class MappedBuffer {
 public:
  MappedBuffer() = default;
  ~MappedBuffer() { destroy(); }
  MappedBuffer(const MappedBuffer&) = delete;
  MappedBuffer& operator=(const MappedBuffer&) = delete;

  // A buffer of max(bytes, 16) bytes; `data` (bytes long, may be null) copied in.
  [[nodiscard]] bool create(VkPhysicalDevice physical_device, VkDevice device, VkDeviceSize bytes, const void* data,
              std::string* error, VkBufferUsageFlags usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
  void destroy();

  VkBuffer buffer() const { return buffer_; }
  VkDeviceSize size() const { return size_; }
  void* mapped() const { return mapped_; }

 private:
  VkDevice device_ = VK_NULL_HANDLE;
  VkBuffer buffer_ = VK_NULL_HANDLE;
  VkDeviceMemory memory_ = VK_NULL_HANDLE;
  VkDeviceSize size_ = 0;
  void* mapped_ = nullptr;
};

}  // namespace foveart::gpu_engine
