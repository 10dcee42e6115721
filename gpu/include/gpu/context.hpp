// The Vulkan device every device stage runs on (docs/gpu.md): its handles,
// what the stages need to know of it (memory types, limits, timestamps), the
// buffers they make on it, and a one-time submission for uploads, tests and
// benchmarks. Frames are recorded into a command buffer of the caller's (the
// layer's frame slot), not through this.
//
// Threads: used from one thread at a time (the layer's frame lock). Nothing
// here throws; failures return false with a message.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "gpu/vk_util.hpp"

namespace foveart::gpu {

// The app's device, and the queue its frames are submitted on.
struct Device {
  VkPhysicalDevice physical_device = VK_NULL_HANDLE;
  VkDevice device = VK_NULL_HANDLE;
  uint32_t queue_family_index = 0;
  uint32_t queue_index = 0;
  // The app enabled bufferDeviceAddress on `device`: the device trace's buffers get addresses.
  bool buffer_device_address = false;
  // Other queue families that use the buffers (the app-recorded trace's): with
  // any, every buffer made here is VK_SHARING_MODE_CONCURRENT over them and queue_family_index.
  std::vector<uint32_t> other_queue_families;
  // The Vulkan version the app's instance asked for (VkApplicationInfo::apiVersion); 0: unknown, the
  // device's version alone decides. The device work uses no more than the lower of the two.
  uint32_t instance_api_version = 0;
};

class Context {
 public:
  // Null with *error when a Vulkan call fails (reconstructor.hpp checks that the shaders can run first).
  static std::unique_ptr<Context> create(const Device& device, std::string* error);
  ~Context();
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;

  const Device& device() const { return device_; }
  VkDevice vk_device() const { return device_.device; }
  const VkPhysicalDeviceMemoryProperties& memory_properties() const { return memory_properties_; }
  // The device's maxStorageBufferRange: the largest buffer one binding reads.
  VkDeviceSize max_storage_buffer_bytes() const { return max_storage_buffer_bytes_; }
  // Timestamps on the queue, and nanoseconds per tick.
  bool timestamps() const { return timestamps_; }
  float timestamp_period_ns() const { return timestamp_period_ns_; }
  // Buffers may have device addresses (Device::buffer_device_address, and the device has the function).
  bool buffer_device_address() const { return get_buffer_address_ != nullptr; }
  // VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT where buffer_device_address(), else 0.
  VkBufferUsageFlags address_usage() const {
    return buffer_device_address() ? VkBufferUsageFlags{VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT} : VkBufferUsageFlags{0};
  }
  // The buffer's device address; 0 without buffer_device_address() (or for no buffer).
  VkDeviceAddress buffer_address(VkBuffer buffer) const;

  // A buffer of at least 16 bytes, host-visible and mapped (b->mapped) or
  // device-local; b->size is set. The caller destroys it (destroy_buffer) either way.
  [[nodiscard]] bool create_buffer(BoundBuffer* b, VkDeviceSize size, VkBufferUsageFlags usage, bool host_visible,
                                   std::string* error) const;

  // Records with `record` into a one-time command buffer, submits it on the
  // queue and waits (table uploads, tests, benchmarks; the layer uses its swapchain's).
  [[nodiscard]] bool submit_and_wait(const std::function<bool(VkCommandBuffer)>& record, std::string* error);

 private:
  Context() = default;
  [[nodiscard]] bool create_submission(std::string* error);

  Device device_;
  VkQueue queue_ = VK_NULL_HANDLE;
  VkPhysicalDeviceMemoryProperties memory_properties_{};
  VkDeviceSize max_storage_buffer_bytes_ = 0;
  float timestamp_period_ns_ = 1.0f;
  bool timestamps_ = false;
  PFN_vkGetBufferDeviceAddress get_buffer_address_ = nullptr;
  std::vector<uint32_t> buffer_families_;  // concurrent sharing: two or more
  VkCommandPool command_pool_ = VK_NULL_HANDLE;
  VkCommandBuffer command_buffer_ = VK_NULL_HANDLE;
  VkFence fence_ = VK_NULL_HANDLE;
};

}  // namespace foveart::gpu
