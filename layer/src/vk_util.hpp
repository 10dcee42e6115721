// Small helpers the layer's Vulkan code shares: a zeroed struct with its
// sType set, and the message for a failed call.
#pragma once

#include <string>

#include <vulkan/vulkan.h>

namespace foveart::layer {

template <class T>
T vk_struct(VkStructureType type) {
  T s{};
  s.sType = type;
  return s;
}

inline std::string vk_error(const char* what, VkResult r) {
  return std::string(what) + " failed (VkResult " + std::to_string(r) + ")";
}

}  // namespace foveart::layer
