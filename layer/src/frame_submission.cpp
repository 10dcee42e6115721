#include "frame_submission.hpp"

#include "gpu/vk_util.hpp"

namespace foveart::layer {
using gpu::vk_error;
using gpu::vk_struct;

std::unique_ptr<FrameSubmission> FrameSubmission::create(const SessionState& session, std::string* error) {
  std::unique_ptr<FrameSubmission> s(new FrameSubmission());
  s->device_ = session.vk_device;
  vkGetDeviceQueue(s->device_, session.vk_queue_family_index, session.vk_queue_index, &s->queue_);
  auto pool_info = vk_struct<VkCommandPoolCreateInfo>(VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO);
  pool_info.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  pool_info.queueFamilyIndex = session.vk_queue_family_index;
  VkResult r = vkCreateCommandPool(s->device_, &pool_info, nullptr, &s->pool_);
  if (r != VK_SUCCESS) return *error = vk_error("vkCreateCommandPool", r), nullptr;
  for (Slot& slot : s->slots_) {
    auto cb_info = vk_struct<VkCommandBufferAllocateInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO);
    cb_info.commandPool = s->pool_;
    cb_info.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    cb_info.commandBufferCount = 1;
    r = vkAllocateCommandBuffers(s->device_, &cb_info, &slot.command_buffer);
    if (r != VK_SUCCESS) return *error = vk_error("vkAllocateCommandBuffers", r), nullptr;
    auto fence_info = vk_struct<VkFenceCreateInfo>(VK_STRUCTURE_TYPE_FENCE_CREATE_INFO);
    r = vkCreateFence(s->device_, &fence_info, nullptr, &slot.fence);
    if (r != VK_SUCCESS) return *error = vk_error("vkCreateFence", r), nullptr;
  }
  return s;
}

FrameSubmission::~FrameSubmission() {
  std::string ignored;
  (void)wait_all(&ignored);
  for (Slot& slot : slots_) {
    if (slot.fence != VK_NULL_HANDLE) vkDestroyFence(device_, slot.fence, nullptr);
  }
  if (pool_ != VK_NULL_HANDLE) vkDestroyCommandPool(device_, pool_, nullptr);
}

bool FrameSubmission::wait(std::uint32_t slot, std::string* error) {
  Slot& s = slots_[slot];
  if (!s.in_flight) return true;
  const VkResult r = vkWaitForFences(device_, 1, &s.fence, VK_TRUE, UINT64_MAX);
  if (r != VK_SUCCESS) return *error = vk_error("vkWaitForFences", r), false;
  s.in_flight = false;
  return true;
}

bool FrameSubmission::wait_all(std::string* error) {
  bool ok = true;
  for (std::uint32_t slot = 0; slot < gpu::kFrameSlots; ++slot) ok = wait(slot, error) && ok;
  return ok;
}

VkCommandBuffer FrameSubmission::begin(std::uint32_t slot, std::string* error) {
  Slot& s = slots_[slot];
  if (s.begun) return s.command_buffer;
  if (s.in_flight) return *error = "frame slot " + std::to_string(slot) + " is still in flight", VK_NULL_HANDLE;
  VkResult r = vkResetCommandBuffer(s.command_buffer, 0);
  auto info = vk_struct<VkCommandBufferBeginInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO);
  info.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  if (r == VK_SUCCESS) r = vkBeginCommandBuffer(s.command_buffer, &info);
  if (r != VK_SUCCESS) return *error = vk_error("vkBeginCommandBuffer", r), VK_NULL_HANDLE;
  s.begun = true;
  return s.command_buffer;
}

bool FrameSubmission::submit(std::uint32_t slot, std::string* error) {
  Slot& s = slots_[slot];
  if (!s.begun) return true;
  s.begun = false;
  VkResult r = vkEndCommandBuffer(s.command_buffer);
  if (r == VK_SUCCESS) r = vkResetFences(device_, 1, &s.fence);
  if (r == VK_SUCCESS) {
    auto submit = vk_struct<VkSubmitInfo>(VK_STRUCTURE_TYPE_SUBMIT_INFO);
    submit.commandBufferCount = 1;
    submit.pCommandBuffers = &s.command_buffer;
    r = vkQueueSubmit(queue_, 1, &submit, s.fence);
  }
  if (r != VK_SUCCESS) return *error = vk_error("frame commands", r), false;
  s.in_flight = true;
  return true;
}

}  // namespace foveart::layer
