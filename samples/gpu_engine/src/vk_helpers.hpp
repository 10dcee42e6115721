// Small helpers the GPU engine's Vulkan code shares: the false-returning error
// report, the message for a failed call, and rounding up to an alignment.
#pragma once

#include <vulkan/vulkan.h>

#include <string>

namespace foveart::gpu_engine {

// Sets *error when given and returns false: `return fail(error, "...");`.
inline bool fail(std::string* error, const std::string& message) {
  if (error) *error = message;
  return false;
}

inline std::string vk_error(const std::string& what, VkResult r) {
  return "gpu_engine: " + what + " failed (VkResult " + std::to_string(static_cast<int>(r)) + ")";
}

// v rounded up to a multiple of alignment (sizes and device addresses alike).
inline VkDeviceSize align_up(VkDeviceSize v, VkDeviceSize alignment) {
  return alignment <= 1 ? v : (v + alignment - 1) / alignment * alignment;
}

}  // namespace foveart::gpu_engine
