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
  for (Slot& slot : s->slots_)
    if (!s->create_slot_objects(&slot.command_buffer, &slot.fence, error)) return nullptr;
  return s;
}

bool FrameSubmission::create_slot_objects(VkCommandBuffer* cb, VkFence* fence, std::string* error) {
  auto cb_info = vk_struct<VkCommandBufferAllocateInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO);
  cb_info.commandPool = pool_;
  cb_info.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  cb_info.commandBufferCount = 1;
  VkResult r = vkAllocateCommandBuffers(device_, &cb_info, cb);
  if (r != VK_SUCCESS) return *error = vk_error("vkAllocateCommandBuffers", r), false;
  auto fence_info = vk_struct<VkFenceCreateInfo>(VK_STRUCTURE_TYPE_FENCE_CREATE_INFO);
  r = vkCreateFence(device_, &fence_info, nullptr, fence);
  if (r != VK_SUCCESS) return *error = vk_error("vkCreateFence", r), false;
  return true;
}

FrameSubmission::~FrameSubmission() {
  std::string ignored;
  (void)wait_all(&ignored);
  for (Slot& slot : slots_) {
    if (slot.rays_in_flight) (void)vkWaitForFences(device_, 1, &slot.rays_fence, VK_TRUE, UINT64_MAX);
    for (VkFence fence : {slot.fence, slot.rays_fence})
      if (fence != VK_NULL_HANDLE) vkDestroyFence(device_, fence, nullptr);
  }
  for (VkSemaphore semaphore : timelines_) vkDestroySemaphore(device_, semaphore, nullptr);
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
    // The app's trace wrote the colours the frame's first commands resolve.
    auto timeline = vk_struct<VkTimelineSemaphoreSubmitInfo>(VK_STRUCTURE_TYPE_TIMELINE_SEMAPHORE_SUBMIT_INFO);
    const VkPipelineStageFlags stage = VK_PIPELINE_STAGE_ALL_COMMANDS_BIT;
    if (s.wait_semaphore != VK_NULL_HANDLE) {
      timeline.waitSemaphoreValueCount = 1;
      timeline.pWaitSemaphoreValues = &s.wait_value;
      submit.pNext = &timeline;
      submit.waitSemaphoreCount = 1;
      submit.pWaitSemaphores = &s.wait_semaphore;
      submit.pWaitDstStageMask = &stage;
    }
    r = vkQueueSubmit(queue_, 1, &submit, s.fence);
  }
  s.wait_semaphore = VK_NULL_HANDLE;
  if (r != VK_SUCCESS) return *error = vk_error("frame commands", r), false;
  s.in_flight = true;
  return true;
}

void FrameSubmission::wait_before(std::uint32_t slot, VkSemaphore semaphore, std::uint64_t value) {
  slots_[slot].wait_semaphore = semaphore;
  slots_[slot].wait_value = value;
}

VkSemaphore FrameSubmission::timeline(std::uint64_t generation, std::string* error) {
  if (!timelines_.empty() && generation == timeline_generation_) return timelines_.back();
  auto type = vk_struct<VkSemaphoreTypeCreateInfo>(VK_STRUCTURE_TYPE_SEMAPHORE_TYPE_CREATE_INFO);
  type.semaphoreType = VK_SEMAPHORE_TYPE_TIMELINE;
  type.initialValue = 0;
  auto info = vk_struct<VkSemaphoreCreateInfo>(VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO);
  info.pNext = &type;
  VkSemaphore semaphore = VK_NULL_HANDLE;
  const VkResult r = vkCreateSemaphore(device_, &info, nullptr, &semaphore);
  if (r != VK_SUCCESS) return *error = vk_error("vkCreateSemaphore (timeline)", r), VK_NULL_HANDLE;
  timelines_.push_back(semaphore);  // an older one may still be signalled by the app: kept
  timeline_generation_ = generation;
  return semaphore;
}

VkCommandBuffer FrameSubmission::begin_rays(std::uint32_t slot, std::string* error) {
  Slot& s = slots_[slot];
  if (s.rays == VK_NULL_HANDLE && !create_slot_objects(&s.rays, &s.rays_fence, error)) return VK_NULL_HANDLE;
  VkResult r = VK_SUCCESS;
  if (s.rays_in_flight) r = vkWaitForFences(device_, 1, &s.rays_fence, VK_TRUE, UINT64_MAX);
  if (r != VK_SUCCESS) return *error = vk_error("vkWaitForFences (rays)", r), VK_NULL_HANDLE;
  s.rays_in_flight = false;
  r = vkResetCommandBuffer(s.rays, 0);
  auto info = vk_struct<VkCommandBufferBeginInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO);
  info.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  if (r == VK_SUCCESS) r = vkBeginCommandBuffer(s.rays, &info);
  if (r != VK_SUCCESS) return *error = vk_error("vkBeginCommandBuffer (rays)", r), VK_NULL_HANDLE;
  return s.rays;
}

bool FrameSubmission::submit_rays(std::uint32_t slot, VkSemaphore semaphore, std::uint64_t value, std::string* error) {
  Slot& s = slots_[slot];
  VkResult r = vkEndCommandBuffer(s.rays);
  if (r == VK_SUCCESS) r = vkResetFences(device_, 1, &s.rays_fence);
  if (r == VK_SUCCESS) {
    // After the previous batch's tracedValue (value - 1, promised by its release): signals stay in order.
    const std::uint64_t previous = value - 1;
    const VkPipelineStageFlags stage = VK_PIPELINE_STAGE_ALL_COMMANDS_BIT;
    auto timeline = vk_struct<VkTimelineSemaphoreSubmitInfo>(VK_STRUCTURE_TYPE_TIMELINE_SEMAPHORE_SUBMIT_INFO);
    timeline.signalSemaphoreValueCount = 1;
    timeline.pSignalSemaphoreValues = &value;
    auto submit = vk_struct<VkSubmitInfo>(VK_STRUCTURE_TYPE_SUBMIT_INFO);
    if (previous > 0) {
      timeline.waitSemaphoreValueCount = 1;
      timeline.pWaitSemaphoreValues = &previous;
      submit.waitSemaphoreCount = 1;
      submit.pWaitSemaphores = &semaphore;
      submit.pWaitDstStageMask = &stage;
    }
    submit.pNext = &timeline;
    submit.commandBufferCount = 1;
    submit.pCommandBuffers = &s.rays;
    submit.signalSemaphoreCount = 1;
    submit.pSignalSemaphores = &semaphore;
    r = vkQueueSubmit(queue_, 1, &submit, s.rays_fence);
  }
  if (r != VK_SUCCESS) return *error = vk_error("ray batch commands", r), false;
  s.rays_in_flight = true;
  return true;
}

}  // namespace foveart::layer
