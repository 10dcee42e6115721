// The GPU path's frames in flight (gpu/frame_slots.hpp, docs/gpu.md "A
// pipelined frame"): per frame slot one command buffer that both eyes record
// into and one fence its single submission on the app's queue signals. Frame n
// uses slot n % kFrameSlots; before recording into a slot the layer waits for
// that slot's previous submission (frame n - kFrameSlots, an older frame),
// never for the frame it just submitted.
//
// Threads: used inside xrEndFrame under the renderer's frame lock, where the
// app may not use the queue (OpenXR spec 10.1). Nothing here throws.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>

#include "gpu/frame_slots.hpp"
#include "state.hpp"  // before the extension header: Vulkan's part of it
#include "layer/XR_FOVEART_foveated_ray_tracing.h"

namespace foveart::layer {

static_assert(gpu::kFrameSlots == XR_FOVEART_DEVICE_TRACE_FRAME_SLOTS,
              "the extension header promises engines this many device-trace frames in flight");

class FrameSubmission {
 public:
  // Null with *error when the device says no.
  static std::unique_ptr<FrameSubmission> create(const SessionState& session, std::string* error);
  ~FrameSubmission();  // waits for what is in flight
  FrameSubmission(const FrameSubmission&) = delete;
  FrameSubmission& operator=(const FrameSubmission&) = delete;

  // Waits until the slot's last submission finished (nothing when it has none); false with *error.
  [[nodiscard]] bool wait(std::uint32_t slot, std::string* error);
  // Waits for every slot.
  [[nodiscard]] bool wait_all(std::string* error);
  // The slot's command buffer, begun (reset first) at the first call after submit();
  // the slot's previous submission must have finished (wait). VK_NULL_HANDLE with *error.
  VkCommandBuffer begin(std::uint32_t slot, std::string* error);
  // Whether the slot's command buffer was begun and not submitted yet.
  bool begun(std::uint32_t slot) const { return slots_[slot].begun; }
  // Ends the slot's command buffer and submits it with the slot's fence; false with *error.
  [[nodiscard]] bool submit(std::uint32_t slot, std::string* error);

 private:
  struct Slot {
    VkCommandBuffer command_buffer = VK_NULL_HANDLE;
    VkFence fence = VK_NULL_HANDLE;
    bool begun = false;
    bool in_flight = false;  // submitted, not waited for yet
  };
  FrameSubmission() = default;

  VkDevice device_ = VK_NULL_HANDLE;
  VkQueue queue_ = VK_NULL_HANDLE;
  VkCommandPool pool_ = VK_NULL_HANDLE;
  std::array<Slot, gpu::kFrameSlots> slots_;
};

}  // namespace foveart::layer
