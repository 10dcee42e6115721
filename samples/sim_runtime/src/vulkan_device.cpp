#include "vulkan_device.h"

#include <cstring>

#include "icd_pin.h"

namespace foveart::sim {
namespace {

template <class Fn>
void load_instance(VkInstance instance, const char* name, Fn& out) {
  out = reinterpret_cast<Fn>(vkGetInstanceProcAddr(instance, name));
}

VkImageAspectFlags aspect_of(bool depth) {
  return depth ? VK_IMAGE_ASPECT_DEPTH_BIT : VK_IMAGE_ASPECT_COLOR_BIT;
}

}  // namespace

bool is_depth_format(VkFormat format) {
  switch (format) {
    case VK_FORMAT_D16_UNORM:
    case VK_FORMAT_D32_SFLOAT:
    case VK_FORMAT_D24_UNORM_S8_UINT:
    case VK_FORMAT_D32_SFLOAT_S8_UINT:
      return true;
    default:
      return false;
  }
}

bool is_capturable_format(VkFormat format, bool& out_bgra) {
  switch (format) {
    case VK_FORMAT_B8G8R8A8_SRGB:
    case VK_FORMAT_B8G8R8A8_UNORM:
      out_bgra = true;
      return true;
    case VK_FORMAT_R8G8B8A8_SRGB:
    case VK_FORMAT_R8G8B8A8_UNORM:
      out_bgra = false;
      return true;
    default:
      return false;
  }
}

bool VulkanDevice::init(VkInstance instance, VkPhysicalDevice physical, VkDevice device,
                        uint32_t queue_family, uint32_t queue_index, std::string* error) {
  pin_loaded_vulkan_icds_and_layers();  // LeakSanitizer must still see them at exit (icd_pin.h)
  instance_ = instance;
  physical_ = physical;
  queue_family_ = queue_family;
  auto get_device_proc = reinterpret_cast<PFN_vkGetDeviceProcAddr>(
      vkGetInstanceProcAddr(instance, "vkGetDeviceProcAddr"));
  PFN_vkGetPhysicalDeviceMemoryProperties get_memory_props = nullptr;
  load_instance(instance, "vkGetPhysicalDeviceMemoryProperties", get_memory_props);
  load_instance(instance, "vkGetPhysicalDeviceImageFormatProperties",
                GetPhysicalDeviceImageFormatProperties);
  if (get_device_proc == nullptr || get_memory_props == nullptr ||
      GetPhysicalDeviceImageFormatProperties == nullptr) {
    *error = "vkGetInstanceProcAddr failed for the application's VkInstance";
    return false;
  }
  get_memory_props(physical, &memory_props_);
  auto dev = [&](const char* name, auto& fn) {
    fn = reinterpret_cast<std::remove_reference_t<decltype(fn)>>(get_device_proc(device, name));
    return fn != nullptr;
  };
  const bool ok =
      dev("vkGetDeviceQueue", GetDeviceQueue) && dev("vkCreateImage", CreateImage) &&
      dev("vkDestroyImage", DestroyImage) &&
      dev("vkGetImageMemoryRequirements", GetImageMemoryRequirements) &&
      dev("vkAllocateMemory", AllocateMemory) && dev("vkFreeMemory", FreeMemory) &&
      dev("vkBindImageMemory", BindImageMemory) && dev("vkCreateBuffer", CreateBuffer) &&
      dev("vkDestroyBuffer", DestroyBuffer) &&
      dev("vkGetBufferMemoryRequirements", GetBufferMemoryRequirements) &&
      dev("vkBindBufferMemory", BindBufferMemory) && dev("vkMapMemory", MapMemory) &&
      dev("vkUnmapMemory", UnmapMemory) && dev("vkCreateCommandPool", CreateCommandPool) &&
      dev("vkDestroyCommandPool", DestroyCommandPool) &&
      dev("vkAllocateCommandBuffers", AllocateCommandBuffers) &&
      dev("vkResetCommandBuffer", ResetCommandBuffer) &&
      dev("vkBeginCommandBuffer", BeginCommandBuffer) &&
      dev("vkEndCommandBuffer", EndCommandBuffer) &&
      dev("vkCmdPipelineBarrier", CmdPipelineBarrier) &&
      dev("vkCmdCopyImageToBuffer", CmdCopyImageToBuffer) && dev("vkQueueSubmit", QueueSubmit) &&
      dev("vkCreateFence", CreateFence) && dev("vkDestroyFence", DestroyFence) &&
      dev("vkWaitForFences", WaitForFences) && dev("vkResetFences", ResetFences) &&
      dev("vkInvalidateMappedMemoryRanges", InvalidateMappedMemoryRanges);
  if (!ok) {
    *error = "vkGetDeviceProcAddr failed for the application's VkDevice";
    return false;
  }
  GetDeviceQueue(device, queue_family, queue_index, &queue_);
  if (queue_ == VK_NULL_HANDLE) {
    *error = "no VkQueue at the binding's queueFamilyIndex/queueIndex";
    return false;
  }
  VkCommandPoolCreateInfo pool_info{};
  pool_info.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO;
  pool_info.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  pool_info.queueFamilyIndex = queue_family;
  if (CreateCommandPool(device, &pool_info, nullptr, &pool_) != VK_SUCCESS) {
    *error = "vkCreateCommandPool failed";
    return false;
  }
  device_ = device;
  VkCommandBufferAllocateInfo alloc{};
  alloc.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO;
  alloc.commandPool = pool_;
  alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  alloc.commandBufferCount = 1;
  VkFenceCreateInfo fence_info{};
  fence_info.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO;
  if (AllocateCommandBuffers(device, &alloc, &cmd_) != VK_SUCCESS ||
      CreateFence(device, &fence_info, nullptr, &fence_) != VK_SUCCESS) {
    *error = "vkAllocateCommandBuffers/vkCreateFence failed";
    destroy();
    return false;
  }
  return true;
}

void VulkanDevice::destroy() {
  if (device_ == VK_NULL_HANDLE) return;
  if (readback_.buffer != VK_NULL_HANDLE) {
    UnmapMemory(device_, readback_.memory);
    DestroyBuffer(device_, readback_.buffer, nullptr);
    FreeMemory(device_, readback_.memory, nullptr);
    readback_ = {};
  }
  if (fence_ != VK_NULL_HANDLE) DestroyFence(device_, fence_, nullptr);
  if (pool_ != VK_NULL_HANDLE) DestroyCommandPool(device_, pool_, nullptr);  // frees cmd_
  fence_ = VK_NULL_HANDLE;
  pool_ = VK_NULL_HANDLE;
  cmd_ = VK_NULL_HANDLE;
  device_ = VK_NULL_HANDLE;
}

int32_t VulkanDevice::memory_type(uint32_t bits, VkMemoryPropertyFlags props) const {
  for (uint32_t i = 0; i < memory_props_.memoryTypeCount; ++i) {
    if ((bits & (1U << i)) != 0 && (memory_props_.memoryTypes[i].propertyFlags & props) == props) {
      return static_cast<int32_t>(i);
    }
  }
  return -1;
}

bool VulkanDevice::supports(VkFormat format, VkImageUsageFlags usage, VkImageCreateFlags flags,
                            uint32_t array_size) const {
  VkImageFormatProperties props{};
  if (GetPhysicalDeviceImageFormatProperties(physical_, format, VK_IMAGE_TYPE_2D,
                                             VK_IMAGE_TILING_OPTIMAL, usage, flags,
                                             &props) != VK_SUCCESS) {
    return false;
  }
  return props.maxArrayLayers >= array_size;
}

bool VulkanDevice::create_image(VkFormat format, uint32_t width, uint32_t height,
                                uint32_t array_size, uint32_t mip_count, VkImageUsageFlags usage,
                                VkImageCreateFlags flags, SwapchainImage& out, std::string* error) {
  VkImageCreateInfo info{};
  info.sType = VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO;
  info.flags = flags;
  info.imageType = VK_IMAGE_TYPE_2D;
  info.format = format;
  info.extent = {width, height, 1};
  info.mipLevels = mip_count;
  info.arrayLayers = array_size;
  info.samples = VK_SAMPLE_COUNT_1_BIT;
  info.tiling = VK_IMAGE_TILING_OPTIMAL;
  info.usage = usage;
  info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  info.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
  if (CreateImage(device_, &info, nullptr, &out.image) != VK_SUCCESS) {
    *error = "vkCreateImage failed";
    return false;
  }
  VkMemoryRequirements req{};
  GetImageMemoryRequirements(device_, out.image, &req);
  const int32_t type = memory_type(req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
  VkMemoryAllocateInfo alloc{};
  alloc.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO;
  alloc.allocationSize = req.size;
  alloc.memoryTypeIndex =
      static_cast<uint32_t>(type < 0 ? memory_type(req.memoryTypeBits, 0) : type);
  if (AllocateMemory(device_, &alloc, nullptr, &out.memory) != VK_SUCCESS ||
      BindImageMemory(device_, out.image, out.memory, 0) != VK_SUCCESS) {
    *error = "vkAllocateMemory/vkBindImageMemory failed";
    destroy_image(out);
    return false;
  }
  return true;
}

void VulkanDevice::destroy_image(SwapchainImage& img) {
  if (device_ == VK_NULL_HANDLE) return;
  if (img.image != VK_NULL_HANDLE) DestroyImage(device_, img.image, nullptr);
  if (img.memory != VK_NULL_HANDLE) FreeMemory(device_, img.memory, nullptr);
  img = {};
}

bool VulkanDevice::submit_and_wait(VkCommandBuffer cmd) {
  VkSubmitInfo submit{};
  submit.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO;
  submit.commandBufferCount = 1;
  submit.pCommandBuffers = &cmd;
  if (ResetFences(device_, 1, &fence_) != VK_SUCCESS) return false;
  if (QueueSubmit(queue_, 1, &submit, fence_) != VK_SUCCESS) return false;
  return WaitForFences(device_, 1, &fence_, VK_TRUE, UINT64_MAX) == VK_SUCCESS;
}

bool VulkanDevice::initialize_layout(SwapchainImage& img, bool depth, uint32_t array_size,
                                     uint32_t mip_count) {
  ResetCommandBuffer(cmd_, 0);
  VkCommandBufferBeginInfo begin{};
  begin.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO;
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  BeginCommandBuffer(cmd_, &begin);
  VkImageMemoryBarrier barrier{};
  barrier.sType = VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER;
  barrier.srcAccessMask = 0;
  barrier.dstAccessMask =
      depth ? (VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT |
               VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT)
            : (VK_ACCESS_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT);
  barrier.oldLayout = VK_IMAGE_LAYOUT_UNDEFINED;
  barrier.newLayout = depth ? VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL
                            : VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
  barrier.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  barrier.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  barrier.image = img.image;
  barrier.subresourceRange = {aspect_of(depth), 0, mip_count, 0, array_size};
  CmdPipelineBarrier(cmd_, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, 0,
                     0, nullptr, 0, nullptr, 1, &barrier);
  EndCommandBuffer(cmd_);
  if (!submit_and_wait(cmd_)) return false;
  img.initialized = true;
  return true;
}

bool VulkanDevice::ensure_readback(VkDeviceSize size) {
  if (readback_.buffer != VK_NULL_HANDLE && readback_.size >= size) return true;
  if (readback_.buffer != VK_NULL_HANDLE) {
    UnmapMemory(device_, readback_.memory);
    DestroyBuffer(device_, readback_.buffer, nullptr);
    FreeMemory(device_, readback_.memory, nullptr);
    readback_ = {};
  }
  VkBufferCreateInfo info{};
  info.sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO;
  info.size = size;
  info.usage = VK_BUFFER_USAGE_TRANSFER_DST_BIT;
  info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  if (CreateBuffer(device_, &info, nullptr, &readback_.buffer) != VK_SUCCESS) return false;
  VkMemoryRequirements req{};
  GetBufferMemoryRequirements(device_, readback_.buffer, &req);
  const int32_t type = memory_type(req.memoryTypeBits, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT);
  VkMemoryAllocateInfo alloc{};
  alloc.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO;
  alloc.allocationSize = req.size;
  alloc.memoryTypeIndex = static_cast<uint32_t>(type);
  if (type < 0 || AllocateMemory(device_, &alloc, nullptr, &readback_.memory) != VK_SUCCESS) {
    DestroyBuffer(device_, readback_.buffer, nullptr);
    readback_ = {};
    return false;
  }
  BindBufferMemory(device_, readback_.buffer, readback_.memory, 0);
  MapMemory(device_, readback_.memory, 0, VK_WHOLE_SIZE, 0, &readback_.mapped);
  readback_.size = size;
  return readback_.mapped != nullptr;
}

bool VulkanDevice::read_back(const SwapchainImage& img, uint32_t layer, int32_t x, int32_t y,
                             uint32_t w, uint32_t h, std::vector<uint8_t>& out_texels) {
  const VkDeviceSize size = static_cast<VkDeviceSize>(w) * h * 4;
  if (!ensure_readback(size)) return false;
  ResetCommandBuffer(cmd_, 0);
  VkCommandBufferBeginInfo begin{};
  begin.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO;
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  BeginCommandBuffer(cmd_, &begin);
  // The app released the image in COLOR_ATTACHMENT_OPTIMAL after submitting its
  // rendering to this queue; the barrier orders our copy after those writes.
  VkImageMemoryBarrier to_src{};
  to_src.sType = VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER;
  to_src.srcAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_SHADER_WRITE_BIT |
                         VK_ACCESS_TRANSFER_WRITE_BIT;
  to_src.dstAccessMask = VK_ACCESS_TRANSFER_READ_BIT;
  to_src.oldLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
  to_src.newLayout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
  to_src.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  to_src.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  to_src.image = img.image;
  to_src.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, layer, 1};
  CmdPipelineBarrier(cmd_, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 0,
                     nullptr, 0, nullptr, 1, &to_src);
  VkBufferImageCopy region{};
  region.bufferOffset = 0;
  region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, layer, 1};
  region.imageOffset = {x, y, 0};
  region.imageExtent = {w, h, 1};
  CmdCopyImageToBuffer(cmd_, img.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, readback_.buffer, 1,
                       &region);
  VkImageMemoryBarrier back = to_src;
  back.srcAccessMask = VK_ACCESS_TRANSFER_READ_BIT;
  back.dstAccessMask = VK_ACCESS_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
  back.oldLayout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
  back.newLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
  VkBufferMemoryBarrier host{};
  host.sType = VK_STRUCTURE_TYPE_BUFFER_MEMORY_BARRIER;
  host.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
  host.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
  host.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  host.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  host.buffer = readback_.buffer;
  host.offset = 0;
  host.size = size;
  CmdPipelineBarrier(cmd_, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 0,
                     nullptr, 1, &host, 0, nullptr);
  CmdPipelineBarrier(cmd_, VK_PIPELINE_STAGE_TRANSFER_BIT,
                     VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT, 0, 0, nullptr, 0, nullptr, 1,
                     &back);
  EndCommandBuffer(cmd_);
  if (!submit_and_wait(cmd_)) return false;
  VkMappedMemoryRange range{};
  range.sType = VK_STRUCTURE_TYPE_MAPPED_MEMORY_RANGE;
  range.memory = readback_.memory;
  range.offset = 0;
  range.size = VK_WHOLE_SIZE;
  InvalidateMappedMemoryRanges(device_, 1, &range);
  out_texels.resize(static_cast<size_t>(size));
  std::memcpy(out_texels.data(), readback_.mapped, static_cast<size_t>(size));
  return true;
}

}  // namespace foveart::sim
