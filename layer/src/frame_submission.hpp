// The GPU path's frames in flight (gpu/frame_slots.hpp, docs/gpu.md "A
// pipelined frame"): per frame slot one command buffer that both eyes record
// into and one fence its single submission on the app's queue signals. Frame n
// uses slot n % kFrameSlots; before recording into a slot the layer waits for
// that slot's previous submission (frame n - kFrameSlots, an older frame),
// never for the frame it just submitted.
//
// The app-recorded trace adds per slot a rays command buffer, submitted at
// xrAcquireFoveatedRayBatchFOVEART and signalling the renderer's timeline
// semaphore, and a wait on that semaphore (the app's tracedValue) before the
// slot's frame commands.
//
// Threads: used inside xrEndFrame (and the acquire) under the renderer's frame
// lock; the queue is the session's, which OpenXR lets the layer use only
// inside xrEndFrame: the acquire's submission is the app's call and says so
// in the extension header. Nothing here throws.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

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
  // Ends the slot's command buffer and submits it with the slot's fence,
  // after the wait set by wait_before, if any; false with *error.
  [[nodiscard]] bool submit(std::uint32_t slot, std::string* error);

  // The app-recorded trace. The timeline semaphore of a generation
  // (RayBatches::semaphore_generation): made at the first call of each, the
  // older ones kept until this is destroyed. VK_NULL_HANDLE with *error.
  VkSemaphore timeline(std::uint64_t generation, std::string* error);
  // The slot's rays command buffer, begun; its previous submission waited for. VK_NULL_HANDLE with *error.
  VkCommandBuffer begin_rays(std::uint32_t slot, std::string* error);
  // Ends and submits it, after `semaphore` reached value - 1 (the previous
  // batch's tracedValue, when value > 1), signalling it to `value`; false with *error.
  [[nodiscard]] bool submit_rays(std::uint32_t slot, VkSemaphore semaphore, std::uint64_t value, std::string* error);
  // The slot's next submit() first waits until `semaphore` reaches `value` (the app's trace).
  void wait_before(std::uint32_t slot, VkSemaphore semaphore, std::uint64_t value);

 private:
  struct Slot {
    VkCommandBuffer command_buffer = VK_NULL_HANDLE;
    VkFence fence = VK_NULL_HANDLE;
    bool begun = false;
    bool in_flight = false;  // submitted, not waited for yet
    // The app-recorded trace: the rays' commands and their fence, made at the slot's first acquire.
    VkCommandBuffer rays = VK_NULL_HANDLE;
    VkFence rays_fence = VK_NULL_HANDLE;
    bool rays_in_flight = false;
    VkSemaphore wait_semaphore = VK_NULL_HANDLE;  // set: submit() waits for wait_value first
    std::uint64_t wait_value = 0;
  };
  FrameSubmission() = default;
  [[nodiscard]] bool create_slot_objects(VkCommandBuffer* cb, VkFence* fence, std::string* error);

  VkDevice device_ = VK_NULL_HANDLE;
  VkQueue queue_ = VK_NULL_HANDLE;
  VkCommandPool pool_ = VK_NULL_HANDLE;
  std::array<Slot, gpu::kFrameSlots> slots_;
  std::vector<VkSemaphore> timelines_;  // one per generation; the last is current
  std::uint64_t timeline_generation_ = 0;
};

}  // namespace foveart::layer
