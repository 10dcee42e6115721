#include "command_slot.hpp"

#include "vk_helpers.hpp"

namespace foveart::gpu_engine {

bool CommandSlot::create(VkDevice device, uint32_t queue_family, std::string* error) {
  destroy();
  device_ = device;
  VkCommandPoolCreateInfo pool_info{};
  pool_info.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO;
  pool_info.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  pool_info.queueFamilyIndex = queue_family;
  VkResult r = vkCreateCommandPool(device_, &pool_info, nullptr, &pool_);
  if (r != VK_SUCCESS) {
    pool_ = VK_NULL_HANDLE;
    return fail(error, vk_error("vkCreateCommandPool", r));
  }
  VkCommandBufferAllocateInfo alloc{};
  alloc.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO;
  alloc.commandPool = pool_;
  alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  alloc.commandBufferCount = 1;
  r = vkAllocateCommandBuffers(device_, &alloc, &cb_);
  if (r != VK_SUCCESS) {
    cb_ = VK_NULL_HANDLE;
    return fail(error, vk_error("vkAllocateCommandBuffers", r));
  }
  VkFenceCreateInfo fence_info{};
  fence_info.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO;
  r = vkCreateFence(device_, &fence_info, nullptr, &fence_);
  if (r != VK_SUCCESS) {
    fence_ = VK_NULL_HANDLE;
    return fail(error, vk_error("vkCreateFence", r));
  }
  return true;
}

void CommandSlot::destroy() {
  if (fence_ != VK_NULL_HANDLE) vkDestroyFence(device_, fence_, nullptr);
  if (pool_ != VK_NULL_HANDLE) vkDestroyCommandPool(device_, pool_, nullptr);  // frees cb_
  fence_ = VK_NULL_HANDLE;
  pool_ = VK_NULL_HANDLE;
  cb_ = VK_NULL_HANDLE;
}

bool CommandSlot::begin(std::string* error) {
  VkResult r = vkResetCommandBuffer(cb_, 0);
  VkCommandBufferBeginInfo begin_info{};
  begin_info.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO;
  begin_info.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  if (r == VK_SUCCESS) r = vkBeginCommandBuffer(cb_, &begin_info);
  return r == VK_SUCCESS || fail(error, vk_error("vkBeginCommandBuffer", r));
}

bool CommandSlot::submit_and_wait(VkQueue queue, uint64_t timeout_ns, const char* what, std::string* error) {
  VkResult r = vkEndCommandBuffer(cb_);
  if (r != VK_SUCCESS) return fail(error, vk_error(std::string("vkEndCommandBuffer (") + what + ")", r));
  VkSubmitInfo submit{};
  submit.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO;
  submit.commandBufferCount = 1;
  submit.pCommandBuffers = &cb_;
  r = vkQueueSubmit(queue, 1, &submit, fence_);
  if (r != VK_SUCCESS) return fail(error, vk_error(std::string("vkQueueSubmit (") + what + ")", r));
  r = vkWaitForFences(device_, 1, &fence_, VK_TRUE, timeout_ns);
  if (r != VK_SUCCESS) {
    vkDeviceWaitIdle(device_);
    vkResetFences(device_, 1, &fence_);
    return fail(error, vk_error(std::string("vkWaitForFences (") + what + ")", r));
  }
  r = vkResetFences(device_, 1, &fence_);
  return r == VK_SUCCESS || fail(error, vk_error("vkResetFences", r));
}

}  // namespace foveart::gpu_engine
