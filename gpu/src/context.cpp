#include "gpu/context.hpp"

#include <algorithm>
#include <vector>

namespace foveart::gpu {

std::unique_ptr<Context> Context::create(const Device& device, std::string* error) {
  std::unique_ptr<Context> c(new Context());
  c->device_ = device;
  for (const uint32_t family : device.other_queue_families)
    if (family != device.queue_family_index) c->buffer_families_.push_back(family);
  if (!c->buffer_families_.empty()) c->buffer_families_.push_back(device.queue_family_index);
  std::sort(c->buffer_families_.begin(), c->buffer_families_.end());
  c->buffer_families_.erase(std::unique(c->buffer_families_.begin(), c->buffer_families_.end()), c->buffer_families_.end());
  vkGetDeviceQueue(device.device, device.queue_family_index, device.queue_index, &c->queue_);
  vkGetPhysicalDeviceMemoryProperties(device.physical_device, &c->memory_properties_);
  VkPhysicalDeviceProperties properties{};
  vkGetPhysicalDeviceProperties(device.physical_device, &properties);
  c->max_storage_buffer_bytes_ = properties.limits.maxStorageBufferRange;
  c->timestamp_period_ns_ = properties.limits.timestampPeriod;
  uint32_t count = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(device.physical_device, &count, nullptr);
  std::vector<VkQueueFamilyProperties> families(count);
  vkGetPhysicalDeviceQueueFamilyProperties(device.physical_device, &count, families.data());
  c->timestamps_ = device.queue_family_index < count && families[device.queue_family_index].timestampValidBits > 0;
  if (device.buffer_device_address) {  // core in Vulkan 1.2, else VK_KHR_buffer_device_address
    auto fn = vkGetDeviceProcAddr(device.device, "vkGetBufferDeviceAddress");
    if (fn == nullptr) fn = vkGetDeviceProcAddr(device.device, "vkGetBufferDeviceAddressKHR");
    c->get_buffer_address_ = reinterpret_cast<PFN_vkGetBufferDeviceAddress>(fn);
  }
  if (!c->create_submission(error)) return nullptr;
  return c;
}

VkDeviceAddress Context::buffer_address(VkBuffer buffer) const {
  if (get_buffer_address_ == nullptr || buffer == VK_NULL_HANDLE) return 0;
  auto info = vk_struct<VkBufferDeviceAddressInfo>(VK_STRUCTURE_TYPE_BUFFER_DEVICE_ADDRESS_INFO);
  info.buffer = buffer;
  return get_buffer_address_(device_.device, &info);
}

bool Context::create_submission(std::string* error) {
  VkDevice dev = device_.device;
  auto pool_info = vk_struct<VkCommandPoolCreateInfo>(VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO);
  pool_info.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  pool_info.queueFamilyIndex = device_.queue_family_index;
  VkResult r = vkCreateCommandPool(dev, &pool_info, nullptr, &command_pool_);
  if (r != VK_SUCCESS) return *error = vk_error("vkCreateCommandPool", r), false;
  auto cb_info = vk_struct<VkCommandBufferAllocateInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO);
  cb_info.commandPool = command_pool_;
  cb_info.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  cb_info.commandBufferCount = 1;
  r = vkAllocateCommandBuffers(dev, &cb_info, &command_buffer_);
  if (r != VK_SUCCESS) return *error = vk_error("vkAllocateCommandBuffers", r), false;
  auto fence_info = vk_struct<VkFenceCreateInfo>(VK_STRUCTURE_TYPE_FENCE_CREATE_INFO);
  r = vkCreateFence(dev, &fence_info, nullptr, &fence_);
  if (r != VK_SUCCESS) return *error = vk_error("vkCreateFence", r), false;
  return true;
}

Context::~Context() {
  VkDevice dev = device_.device;
  if (dev == VK_NULL_HANDLE) return;
  if (fence_ != VK_NULL_HANDLE) vkDestroyFence(dev, fence_, nullptr);
  if (command_pool_ != VK_NULL_HANDLE) vkDestroyCommandPool(dev, command_pool_, nullptr);
}

bool Context::create_buffer(BoundBuffer* b, VkDeviceSize size, VkBufferUsageFlags usage, bool host_visible,
                            std::string* error) const {
  b->size = std::max<VkDeviceSize>(size, 16);
  return create_bound_buffer(device_.device, memory_properties_, b->size, usage, buffer_memory_flags(host_visible),
                             &b->buffer, &b->memory, host_visible ? &b->mapped : nullptr, error, buffer_families_);
}

bool Context::submit_and_wait(const std::function<bool(VkCommandBuffer)>& record, std::string* error) {
  VkDevice dev = device_.device;
  VkResult r = vkResetCommandBuffer(command_buffer_, 0);
  auto begin = vk_struct<VkCommandBufferBeginInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO);
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  if (r == VK_SUCCESS) r = vkBeginCommandBuffer(command_buffer_, &begin);
  if (r != VK_SUCCESS) return *error = vk_error("vkBeginCommandBuffer", r), false;
  const bool recorded = record(command_buffer_);
  r = vkEndCommandBuffer(command_buffer_);
  if (!recorded) return false;
  if (r == VK_SUCCESS) r = vkResetFences(dev, 1, &fence_);
  auto submit = vk_struct<VkSubmitInfo>(VK_STRUCTURE_TYPE_SUBMIT_INFO);
  submit.commandBufferCount = 1;
  submit.pCommandBuffers = &command_buffer_;
  if (r == VK_SUCCESS) r = vkQueueSubmit(queue_, 1, &submit, fence_);
  if (r == VK_SUCCESS) r = vkWaitForFences(dev, 1, &fence_, VK_TRUE, UINT64_MAX);
  if (r != VK_SUCCESS) return *error = vk_error("GPU submission", r), false;
  return true;
}

}  // namespace foveart::gpu
