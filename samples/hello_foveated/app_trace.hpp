// --trace-model app: the engine's device trace recorded in the app's own
// command buffers and submitted by the app (the extension header's
// app-recorded trace). Per frame slot one command buffer and fence of the
// app's; each frame's batch is traced into the slot's buffer, which waits for
// the batch's raysReadyValue and signals its tracedValue on the trace queue.
#pragma once

#include <array>
#include <cstdint>

#define XR_USE_GRAPHICS_API_VULKAN
#include <openxr/openxr.h>
#include <vulkan/vulkan.h>

#include "command_pool.hpp"
#include "layer/XR_FOVEART_foveated_ray_tracing.h"

namespace foveart::hello {

class AppRecordedTrace {
 public:
  // The trace queue's family and the queue (a second queue where the device has one). Throws on failure.
  AppRecordedTrace(VkDevice device, uint32_t queue_family_index, VkQueue queue);
  ~AppRecordedTrace();  // waits for its submissions
  AppRecordedTrace(const AppRecordedTrace&) = delete;
  AppRecordedTrace& operator=(const AppRecordedTrace&) = delete;

  // Records `engine` for every view of `batch` with rays into the app's command
  // buffer of the batch's frame slot, and submits it: wait raysReadyValue,
  // signal tracedValue. Throws on a Vulkan failure or the trace's error.
  void trace(const XrFoveatedRayBatchFOVEART& batch, PFN_xrFoveatedTraceRaysDeviceFOVEART engine, void* user_data);

 private:
  VkDevice device_ = VK_NULL_HANDLE;
  VkQueue queue_ = VK_NULL_HANDLE;
  CommandPool slots_;  // a command buffer and fence per frame slot
  std::array<bool, XR_FOVEART_DEVICE_TRACE_FRAME_SLOTS> in_flight_{};
};

}  // namespace foveart::hello
