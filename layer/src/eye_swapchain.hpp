// A swapchain the layer owns for one eye, created through the runtime on the
// app's Vulkan device, and the two ways a frame gets into it: the CPU path's
// upload from a host-visible staging buffer, or the GPU path's commands
// (gpu/eye.hpp) recorded into the frame's command buffer (frame_submission.hpp).
//
// Sync: each frame acquires and waits for an image (xrAcquire/xrWait) and
// records its commands (ending with UNDEFINED -> TRANSFER_DST, a
// buffer-to-image copy and TRANSFER_DST -> COLOR_ATTACHMENT_OPTIMAL, the
// layout OpenXR requires at release). The CPU path's upload submits on the
// app's queue with this swapchain's fence, waits and releases; the GPU path
// releases the image after the frame's one submission, without waiting: the
// runtime orders its use of the image after that submission on the same queue
// (OpenXR 10.1: work submitted before release). All inside xrEndFrame, where
// the app may not use the queue.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "state.hpp"

namespace foveart::layer {

class EyeSwapchain {
 public:
  // Null with *error set when the runtime or the device says no. The
  // staging buffer (CPU path) is made on first use.
  static std::unique_ptr<EyeSwapchain> create(const SessionState& session, uint32_t width_px, uint32_t height_px,
                                              std::string* error);
  ~EyeSwapchain();
  EyeSwapchain(const EyeSwapchain&) = delete;
  EyeSwapchain& operator=(const EyeSwapchain&) = delete;

  uint32_t width_px() const { return width_px_; }
  uint32_t height_px() const { return height_px_; }
  bool srgb() const { return srgb_; }
  XrSwapchain handle() const { return swapchain_; }

  // Rows of width_px RGBA8 texels (already sRGB-encoded when srgb()); null
  // with *error when the buffer cannot be made.
  uint8_t* staging(std::string* error);

  // Copies the staging buffer into the next swapchain image; false with a message on failure
  // (the image is released either way when it was acquired).
  [[nodiscard]] bool upload(std::string* error);

  // Acquires the next image and waits for it: *image; false with *error (nothing held then).
  [[nodiscard]] bool acquire(VkImage* image, std::string* error);
  // Releases the image acquire() gave; false with *error.
  [[nodiscard]] bool release(std::string* error);

  // Acquires the next image, records `record(cb, image)` (which must leave the
  // image in COLOR_ATTACHMENT_OPTIMAL) into this swapchain's command buffer,
  // submits, waits and releases.
  using RecordFn = std::function<bool(VkCommandBuffer cb, VkImage image, std::string* error)>;
  [[nodiscard]] bool present(const RecordFn& record, std::string* error);

 private:
  EyeSwapchain() = default;
  [[nodiscard]] bool create_staging(std::string* error);

  const NextDispatch* next_ = nullptr;
  VkDevice device_ = VK_NULL_HANDLE;
  VkQueue queue_ = VK_NULL_HANDLE;
  XrSwapchain swapchain_ = XR_NULL_HANDLE;
  std::vector<VkImage> images_;
  uint32_t width_px_ = 0;
  uint32_t height_px_ = 0;
  bool srgb_ = false;
  VkPhysicalDevice physical_device_ = VK_NULL_HANDLE;
  VkBuffer buffer_ = VK_NULL_HANDLE;
  VkDeviceMemory memory_ = VK_NULL_HANDLE;
  void* mapped_ = nullptr;
  VkCommandPool pool_ = VK_NULL_HANDLE;
  VkCommandBuffer command_buffer_ = VK_NULL_HANDLE;
  VkFence fence_ = VK_NULL_HANDLE;
  std::shared_ptr<InstanceState> instance_;  // keeps next_ alive
};

}  // namespace foveart::layer
