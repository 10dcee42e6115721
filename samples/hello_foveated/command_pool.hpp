// The sample's own command recording (xr_app.cpp's grey frame, app_trace.cpp's trace slots,
// full_frame.cpp's full render): a resettable command pool on a queue family, primary command
// buffers from it and an unsignalled fence per buffer.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <vulkan/vulkan.h>

namespace foveart::hello {

struct CommandPool {
  VkCommandPool pool = VK_NULL_HANDLE;
  std::vector<VkCommandBuffer> buffers;
  std::vector<VkFence> fences;  // one per buffer

  // `count` buffers and fences on `queue_family`. Throws std::runtime_error naming the failed
  // call and `who`, having freed what it made.
  void create(VkDevice device, std::uint32_t queue_family, std::size_t count, const char* who);
  // Frees the fences and the pool (its buffers with it); nothing of theirs may be in flight.
  void destroy(VkDevice device) noexcept;
};

}  // namespace foveart::hello
