// CommandSlot: one primary command buffer with its pool and fence, for the GPU
// engine's synchronous work (scene uploads, acceleration structure builds, the
// ray callback's submissions): begin, record, submit and wait, again.
#pragma once

#include <vulkan/vulkan.h>

#include <cstdint>
#include <string>

namespace foveart::gpu_engine {

class CommandSlot {
 public:
  CommandSlot() = default;
  ~CommandSlot() { destroy(); }
  CommandSlot(const CommandSlot&) = delete;
  CommandSlot& operator=(const CommandSlot&) = delete;

  // The pool (its buffers reset one by one), the buffer and an unsignalled fence on `queue_family`.
  [[nodiscard]] bool create(VkDevice device, uint32_t queue_family, std::string* error);
  // Frees the buffer with its pool, and the fence; the device must still live. Idempotent.
  void destroy();
  bool created() const { return cb_ != VK_NULL_HANDLE; }
  VkCommandBuffer cb() const { return cb_; }

  // Resets the buffer and begins a one-time recording.
  [[nodiscard]] bool begin(std::string* error);
  // Ends a recording that will not be submitted.
  void abandon() { vkEndCommandBuffer(cb_); }
  // Ends the recording, submits it to `queue` and waits up to timeout_ns; the fence is reset
  // for the next. After a failed wait the device is idled, so that nothing recorded still runs
  // when the caller reuses what the commands read. `what` names the work in the error.
  [[nodiscard]] bool submit_and_wait(VkQueue queue, uint64_t timeout_ns, const char* what, std::string* error);

 private:
  VkDevice device_ = VK_NULL_HANDLE;
  VkCommandPool pool_ = VK_NULL_HANDLE;
  VkCommandBuffer cb_ = VK_NULL_HANDLE;
  VkFence fence_ = VK_NULL_HANDLE;
};

}  // namespace foveart::gpu_engine
