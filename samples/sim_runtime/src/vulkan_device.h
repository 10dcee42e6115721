// The runtime's view of the application's Vulkan device (from the session's
// XrGraphicsBindingVulkan2KHR): swapchain images, layout transitions and the
// capture readback, all recorded on the application's queue with fences.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "xr_includes.h"

namespace foveart::sim {

struct SwapchainImage {
  VkImage image = VK_NULL_HANDLE;
  VkDeviceMemory memory = VK_NULL_HANDLE;
  bool initialized = false;  // transitioned to the attachment layout once
};

struct ReadbackBuffer {
  VkBuffer buffer = VK_NULL_HANDLE;
  VkDeviceMemory memory = VK_NULL_HANDLE;
  VkDeviceSize size = 0;
  void* mapped = nullptr;
};

class VulkanDevice {
 public:
  // Fails (returns false, error filled) when the binding's handles are unusable.
  [[nodiscard]] bool init(VkInstance instance, VkPhysicalDevice physical, VkDevice device, uint32_t queue_family,
            uint32_t queue_index, std::string* error);
  void destroy();
  bool valid() const { return device_ != VK_NULL_HANDLE; }

  bool supports(VkFormat format, VkImageUsageFlags usage, VkImageCreateFlags flags,
                uint32_t array_size) const;
  [[nodiscard]] bool create_image(VkFormat format, uint32_t width, uint32_t height, uint32_t array_size,
                    uint32_t mip_count, VkImageUsageFlags usage, VkImageCreateFlags flags,
                    SwapchainImage& out, std::string* error);
  void destroy_image(SwapchainImage& img);
  // UNDEFINED -> attachment layout, on the app's queue, waited.
  bool initialize_layout(SwapchainImage& img, bool depth, uint32_t array_size, uint32_t mip_count);
  // Copies rect of (image, layer) into host memory as tightly packed 4-byte texels.
  bool read_back(const SwapchainImage& img, uint32_t layer, int32_t x, int32_t y, uint32_t w,
                 uint32_t h, std::vector<uint8_t>& out_texels);

 private:
  bool submit_and_wait(VkCommandBuffer cmd);
  bool ensure_readback(VkDeviceSize size);
  int32_t memory_type(uint32_t bits, VkMemoryPropertyFlags props) const;

  VkInstance instance_ = VK_NULL_HANDLE;
  VkPhysicalDevice physical_ = VK_NULL_HANDLE;
  VkDevice device_ = VK_NULL_HANDLE;
  VkQueue queue_ = VK_NULL_HANDLE;
  uint32_t queue_family_ = 0;
  VkCommandPool pool_ = VK_NULL_HANDLE;
  VkCommandBuffer cmd_ = VK_NULL_HANDLE;
  VkFence fence_ = VK_NULL_HANDLE;
  VkPhysicalDeviceMemoryProperties memory_props_{};
  ReadbackBuffer readback_;

  PFN_vkGetPhysicalDeviceImageFormatProperties GetPhysicalDeviceImageFormatProperties = nullptr;
  PFN_vkGetDeviceQueue GetDeviceQueue = nullptr;
  PFN_vkCreateImage CreateImage = nullptr;
  PFN_vkDestroyImage DestroyImage = nullptr;
  PFN_vkGetImageMemoryRequirements GetImageMemoryRequirements = nullptr;
  PFN_vkAllocateMemory AllocateMemory = nullptr;
  PFN_vkFreeMemory FreeMemory = nullptr;
  PFN_vkBindImageMemory BindImageMemory = nullptr;
  PFN_vkCreateBuffer CreateBuffer = nullptr;
  PFN_vkDestroyBuffer DestroyBuffer = nullptr;
  PFN_vkGetBufferMemoryRequirements GetBufferMemoryRequirements = nullptr;
  PFN_vkBindBufferMemory BindBufferMemory = nullptr;
  PFN_vkMapMemory MapMemory = nullptr;
  PFN_vkUnmapMemory UnmapMemory = nullptr;
  PFN_vkCreateCommandPool CreateCommandPool = nullptr;
  PFN_vkDestroyCommandPool DestroyCommandPool = nullptr;
  PFN_vkAllocateCommandBuffers AllocateCommandBuffers = nullptr;
  PFN_vkResetCommandBuffer ResetCommandBuffer = nullptr;
  PFN_vkBeginCommandBuffer BeginCommandBuffer = nullptr;
  PFN_vkEndCommandBuffer EndCommandBuffer = nullptr;
  PFN_vkCmdPipelineBarrier CmdPipelineBarrier = nullptr;
  PFN_vkCmdCopyImageToBuffer CmdCopyImageToBuffer = nullptr;
  PFN_vkQueueSubmit QueueSubmit = nullptr;
  PFN_vkCreateFence CreateFence = nullptr;
  PFN_vkDestroyFence DestroyFence = nullptr;
  PFN_vkWaitForFences WaitForFences = nullptr;
  PFN_vkResetFences ResetFences = nullptr;
  PFN_vkInvalidateMappedMemoryRanges InvalidateMappedMemoryRanges = nullptr;
};

bool is_depth_format(VkFormat format);
// Texel layout of formats the capture understands: 4 bytes, BGRA order or RGBA order.
bool is_capturable_format(VkFormat format, bool& out_bgra);

}  // namespace foveart::sim
