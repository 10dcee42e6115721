#include "app_trace.hpp"

#include <stdexcept>
#include <string>

namespace foveart::hello {
namespace {

template <class T>
T trace_vk_struct(VkStructureType type) {
  T s{};
  s.sType = type;
  return s;
}

void check_trace(VkResult r, const char* what) {
  if (r != VK_SUCCESS) throw std::runtime_error(std::string(what) + " failed: VkResult " + std::to_string(r));
}

}  // namespace

AppRecordedTrace::AppRecordedTrace(VkDevice device, uint32_t queue_family_index, VkQueue queue)
    : device_(device), queue_(queue) {
  slots_.create(device_, queue_family_index, in_flight_.size(), "app trace");
}

AppRecordedTrace::~AppRecordedTrace() {
  for (std::size_t s = 0; s < slots_.fences.size(); ++s)
    if (in_flight_[s]) (void)vkWaitForFences(device_, 1, &slots_.fences[s], VK_TRUE, UINT64_MAX);
  slots_.destroy(device_);
}

void AppRecordedTrace::trace(const XrFoveatedRayBatchFOVEART& batch, PFN_xrFoveatedTraceRaysDeviceFOVEART engine,
                             void* user_data) {
  uint64_t frame_index = 0;
  for (uint32_t v = 0; v < batch.viewCountOutput; ++v)
    if (batch.views[v].rayCapacity > 0) frame_index = batch.views[v].frameIndex;
  // The slot's last trace finished: its command buffer, and the engine's resources of that slot, are free.
  const std::size_t slot = frame_index % slots_.buffers.size();
  VkFence& fence = slots_.fences[slot];
  if (in_flight_[slot]) check_trace(vkWaitForFences(device_, 1, &fence, VK_TRUE, UINT64_MAX), "vkWaitForFences");
  in_flight_[slot] = false;
  const VkCommandBuffer cb = slots_.buffers[slot];
  check_trace(vkResetCommandBuffer(cb, 0), "vkResetCommandBuffer");
  auto begin = trace_vk_struct<VkCommandBufferBeginInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO);
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  check_trace(vkBeginCommandBuffer(cb, &begin), "vkBeginCommandBuffer");
  XrResult traced = XR_SUCCESS;
  for (uint32_t v = 0; v < batch.viewCountOutput && XR_SUCCEEDED(traced); ++v) {
    if (batch.views[v].rayCapacity == 0) continue;  // not traced this frame
    XrFoveatedDeviceRayBatchFOVEART view = batch.views[v];
    view.commandBuffer = cb;  // the engine's recorder, into the app's own command buffer
    traced = engine(user_data, &view);
  }
  check_trace(vkEndCommandBuffer(cb), "vkEndCommandBuffer");
  // Submitted even when a view failed: the layer waits for tracedValue once the batch is released.
  const VkPipelineStageFlags stage = VK_PIPELINE_STAGE_ALL_COMMANDS_BIT;
  auto timeline = trace_vk_struct<VkTimelineSemaphoreSubmitInfo>(VK_STRUCTURE_TYPE_TIMELINE_SEMAPHORE_SUBMIT_INFO);
  timeline.waitSemaphoreValueCount = 1;
  timeline.pWaitSemaphoreValues = &batch.raysReadyValue;
  timeline.signalSemaphoreValueCount = 1;
  timeline.pSignalSemaphoreValues = &batch.tracedValue;
  auto submit = trace_vk_struct<VkSubmitInfo>(VK_STRUCTURE_TYPE_SUBMIT_INFO);
  submit.pNext = &timeline;
  submit.waitSemaphoreCount = 1;
  submit.pWaitSemaphores = &batch.semaphore;
  submit.pWaitDstStageMask = &stage;
  submit.commandBufferCount = 1;
  submit.pCommandBuffers = &cb;
  submit.signalSemaphoreCount = 1;
  submit.pSignalSemaphores = &batch.semaphore;
  check_trace(vkResetFences(device_, 1, &fence), "vkResetFences");
  check_trace(vkQueueSubmit(queue_, 1, &submit, fence), "vkQueueSubmit (app trace)");
  in_flight_[slot] = true;
  if (XR_FAILED(traced)) throw std::runtime_error("the device trace failed: XrResult " + std::to_string(traced));
}

}  // namespace foveart::hello
