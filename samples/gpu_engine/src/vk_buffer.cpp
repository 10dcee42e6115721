// MemoryLedger (memory types, fallback, accounting), MappedBuffer, DeviceBuffer
// and the staging Uploader.
#include "vk_buffer.hpp"
#include "vk_helpers.hpp"

#include <algorithm>
#include <cstdint>
#include <cstring>

namespace foveart::gpu_engine {
namespace {

constexpr VkMemoryPropertyFlags kHost = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
constexpr uint64_t kUploadTimeoutNs = 60ull * 1000 * 1000 * 1000;

// The first memory type allowed by `bits` with all of `flags` and none of
// `avoid`; UINT32_MAX if none.
uint32_t find_memory_type(const VkPhysicalDeviceMemoryProperties& props, uint32_t bits, VkMemoryPropertyFlags flags,
                          VkMemoryPropertyFlags avoid = 0) {
  for (uint32_t i = 0; i < props.memoryTypeCount; ++i) {
    const VkMemoryPropertyFlags f = props.memoryTypes[i].propertyFlags;
    if ((bits & (1u << i)) != 0 && (f & flags) == flags && (f & avoid) == 0) return i;
  }
  return UINT32_MAX;
}

uint32_t find_memory_type(VkPhysicalDevice physical_device, uint32_t bits, VkMemoryPropertyFlags flags) {
  VkPhysicalDeviceMemoryProperties props{};
  vkGetPhysicalDeviceMemoryProperties(physical_device, &props);
  return find_memory_type(props, bits, flags);
}

VkResult allocate_type(VkDevice device, VkDeviceSize bytes, uint32_t type, bool device_address, VkDeviceMemory* out) {
  VkMemoryAllocateInfo alloc{};
  alloc.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO;
  alloc.allocationSize = bytes;
  alloc.memoryTypeIndex = type;
  VkMemoryAllocateFlagsInfo flags{};
  flags.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_FLAGS_INFO;
  flags.flags = VK_MEMORY_ALLOCATE_DEVICE_ADDRESS_BIT;
  if (device_address) alloc.pNext = &flags;
  return vkAllocateMemory(device, &alloc, nullptr, out);
}

}  // namespace

// ---- MemoryLedger ------------------------------------------------------------------------

MemoryLedger::MemoryLedger(VkPhysicalDevice physical_device, VkDevice device, bool device_local_allowed)
    : physical_(physical_device), device_(device), device_local_allowed_(device_local_allowed) {
  vkGetPhysicalDeviceMemoryProperties(physical_, &props_);
  if (!device_local_allowed_) note_fallback("device-local memory disabled by GpuTracerOptions::device_local_memory");
}

void MemoryLedger::note_fallback(const std::string& why) {
  if (fallback_.empty())
    fallback_ = "gpu_engine: the scene lives in host-visible memory, read by the device over the bus (" + why + ")";
}

bool MemoryLedger::allocate(const VkMemoryRequirements& req, bool device_address, bool texture, Allocation* out,
                            std::string* error) {
  *out = Allocation{};
  out->texture = texture;
  out->bytes = req.size;
  if (device_local_allowed_) {
    // Device-local, preferably not host-visible (the big heap on a discrete card); filled through staging.
    uint32_t type = find_memory_type(props_, req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT,
                                     VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT);
    if (type == UINT32_MAX) type = find_memory_type(props_, req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    VkResult r = VK_ERROR_OUT_OF_DEVICE_MEMORY;
    if (type != UINT32_MAX) r = allocate_type(device_, req.size, type, device_address, &out->memory);
    if (r == VK_SUCCESS) {
      out->device_local = true;
      use_.device_local_bytes += req.size;
      if (texture) use_.texture_bytes += req.size;
      return true;
    }
    note_fallback(type == UINT32_MAX ? "no device-local memory type fits"
                                     : "allocating " + std::to_string(req.size) + " device-local bytes failed (VkResult " +
                                           std::to_string(static_cast<int>(r)) + ")");
  }
  const uint32_t type = find_memory_type(props_, req.memoryTypeBits, kHost);
  if (type == UINT32_MAX) return fail(error, "gpu_engine: no host-visible coherent memory type for the scene");
  const VkResult r = allocate_type(device_, req.size, type, device_address, &out->memory);
  if (r != VK_SUCCESS) {
    out->memory = VK_NULL_HANDLE;
    return fail(error, "gpu_engine: allocating " + std::to_string(req.size) + " bytes failed (VkResult " +
                           std::to_string(static_cast<int>(r)) + ")");
  }
  out->host_visible = true;
  out->device_local = (props_.memoryTypes[type].propertyFlags & VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT) != 0 &&
                      device_local_allowed_;
  (out->device_local ? use_.device_local_bytes : use_.host_visible_bytes) += req.size;
  if (texture) use_.texture_bytes += req.size;
  return true;
}

void MemoryLedger::release(Allocation* a) {
  if (a->memory == VK_NULL_HANDLE) return;
  vkFreeMemory(device_, a->memory, nullptr);  // unmaps implicitly
  (a->device_local ? use_.device_local_bytes : use_.host_visible_bytes) -= a->bytes;
  if (a->texture) use_.texture_bytes -= a->bytes;
  *a = Allocation{};
}

// ---- MappedBuffer ------------------------------------------------------------------------

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
  const bool device_address = (usage & VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT) != 0;
  uint32_t type = find_memory_type(physical_device, req.memoryTypeBits, kHost | VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
  r = VK_ERROR_OUT_OF_DEVICE_MEMORY;
  if (type != UINT32_MAX)  // device-local host-visible heaps can be small: fall back below
    r = allocate_type(device, req.size, type, device_address, &memory_);
  if (r != VK_SUCCESS) {
    memory_ = VK_NULL_HANDLE;
    type = find_memory_type(physical_device, req.memoryTypeBits, kHost);
    if (type == UINT32_MAX) {
      if (error) *error = "gpu_engine: no host-visible coherent memory type for a storage buffer";
      destroy();
      return false;
    }
    r = allocate_type(device, req.size, type, device_address, &memory_);
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

// ---- DeviceBuffer ------------------------------------------------------------------------

bool DeviceBuffer::create(const std::shared_ptr<MemoryLedger>& ledger, VkDeviceSize bytes, VkBufferUsageFlags usage,
                          std::string* error) {
  destroy();
  ledger_ = ledger;
  size_ = std::max<VkDeviceSize>(bytes, 16);
  VkBufferCreateInfo info{};
  info.sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO;
  info.size = size_;
  info.usage = usage | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
  info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  const VkDevice device = ledger->device();
  VkResult r = vkCreateBuffer(device, &info, nullptr, &buffer_);
  if (r != VK_SUCCESS) {
    buffer_ = VK_NULL_HANDLE;
    return fail(error, vk_error("vkCreateBuffer", r));
  }
  VkMemoryRequirements req{};
  vkGetBufferMemoryRequirements(device, buffer_, &req);
  const bool device_address = (usage & VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT) != 0;
  if (!ledger->allocate(req, device_address, false, &allocation_, error)) {
    destroy();
    return false;
  }
  r = vkBindBufferMemory(device, buffer_, allocation_.memory, 0);
  if (r == VK_SUCCESS && allocation_.host_visible)  // the fallback: filled by the host directly
    r = vkMapMemory(device, allocation_.memory, 0, VK_WHOLE_SIZE, 0, &mapped_);
  if (r != VK_SUCCESS) {
    destroy();
    return fail(error, vk_error("binding or mapping buffer memory", r));
  }
  if (mapped_ != nullptr) std::memset(mapped_, 0, static_cast<size_t>(size_));
  return true;
}

void DeviceBuffer::destroy() {
  if (ledger_ == nullptr) return;
  if (buffer_ != VK_NULL_HANDLE) vkDestroyBuffer(ledger_->device(), buffer_, nullptr);
  ledger_->release(&allocation_);
  buffer_ = VK_NULL_HANDLE;
  mapped_ = nullptr;
  size_ = 0;
  ledger_.reset();
}

// ---- Uploader ----------------------------------------------------------------------------

Uploader::Uploader(VkPhysicalDevice physical_device, VkDevice device, uint32_t queue_family, VkQueue queue)
    : physical_(physical_device), device_(device), family_(queue_family), queue_(queue) {}

bool Uploader::begin(std::string* error) {
  if (recording_) return true;
  if (queue_ == VK_NULL_HANDLE) return fail(error, "gpu_engine: uploading the scene needs GpuContext::queue");
  if (!commands_.created() && !commands_.create(device_, family_, error)) return false;
  if (!commands_.begin(error)) return false;
  recording_ = true;
  return true;
}

// Copies (and layout transitions) -> every later command's reads; submit, wait, release the staging.
bool Uploader::submit(std::string* error) {
  if (!recording_) return true;
  recording_ = false;
  VkMemoryBarrier visible{};
  visible.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER;
  visible.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
  visible.dstAccessMask = VK_ACCESS_MEMORY_READ_BIT | VK_ACCESS_SHADER_READ_BIT;
  vkCmdPipelineBarrier(commands_.cb(), VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, 0, 1,
                       &visible, 0, nullptr, 0, nullptr);
  if (!commands_.submit_and_wait(queue_, kUploadTimeoutNs, "scene upload", error)) return false;
  staging_.clear();
  staged_bytes_ = 0;
  return true;
}

bool Uploader::finish(std::string* error) { return submit(error); }

// A staging buffer holding `data`, the recording begun; earlier staging submitted first when it grew large.
MappedBuffer* Uploader::stage(const void* data, VkDeviceSize bytes, std::string* error) {
  if (staged_bytes_ > 0 && staged_bytes_ + bytes > kFlushBytes && !submit(error)) return nullptr;
  if (!begin(error)) return nullptr;
  auto staging = std::make_unique<MappedBuffer>();
  if (!staging->create(physical_, device_, bytes, data, error, VK_BUFFER_USAGE_TRANSFER_SRC_BIT)) return nullptr;
  staged_bytes_ += bytes;
  staging_.push_back(std::move(staging));
  return staging_.back().get();
}

bool Uploader::buffer(const DeviceBuffer& dst, const void* data, VkDeviceSize bytes, std::string* error) {
  if (bytes == 0 || data == nullptr) return true;
  if (bytes > dst.size()) return fail(error, "gpu_engine: upload larger than its buffer");
  if (dst.mapped() != nullptr) {  // the host-visible fallback: no staging
    std::memcpy(dst.mapped(), data, static_cast<size_t>(bytes));
    return true;
  }
  MappedBuffer* staging = stage(data, bytes, error);
  if (staging == nullptr) return false;
  const VkBufferCopy copy{0, 0, bytes};
  vkCmdCopyBuffer(commands_.cb(), staging->buffer(), dst.buffer(), 1, &copy);
  return true;
}

bool Uploader::image(VkImage dst, uint32_t width, uint32_t height, uint32_t texel_bytes, const void* data,
                     std::string* error, uint32_t level) {
  MappedBuffer* staging = stage(data, VkDeviceSize{width} * height * texel_bytes, error);
  if (staging == nullptr) return false;
  VkImageMemoryBarrier b{};
  b.sType = VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER;
  b.srcAccessMask = 0;
  b.dstAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
  b.oldLayout = VK_IMAGE_LAYOUT_UNDEFINED;
  b.newLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
  b.srcQueueFamilyIndex = b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  b.image = dst;
  b.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, level, 1, 0, 1};
  vkCmdPipelineBarrier(commands_.cb(), VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 0, nullptr,
                       0, nullptr, 1, &b);
  VkBufferImageCopy copy{};
  copy.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, level, 0, 1};
  copy.imageExtent = {width, height, 1};
  vkCmdCopyBufferToImage(commands_.cb(), staging->buffer(), dst, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &copy);
  // The layout the shaders sample in; its visibility to them comes with submit()'s barrier.
  b.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
  b.dstAccessMask = VK_ACCESS_SHADER_READ_BIT;
  b.oldLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
  b.newLayout = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
  vkCmdPipelineBarrier(commands_.cb(), VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, 0, 0,
                       nullptr, 0, nullptr, 1, &b);
  return true;
}

}  // namespace foveart::gpu_engine
