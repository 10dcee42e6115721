// Whether GPU timestamps can time work (the GPU benchmark's check, docs/gpu.md
// "Speed"): a queue family without timestamp bits, a zero period, or stamps
// around work that read 0 or do not advance give no time, and a benchmark
// printing 0 ms from them would call any budget met. Each function returns ""
// when the timestamps are usable, else one line naming the device.
#pragma once

#include <vulkan/vulkan.h>

#include <cstdint>
#include <string>
#include <vector>

namespace foveart::gpu_engine {

// Of a queue family's timestampValidBits and the device's timestampPeriod.
inline std::string timestamp_support_problem(const std::string& device, uint32_t valid_bits, float period_ns) {
  if (valid_bits == 0)
    return device + ": its queue family has no timestamps (timestampValidBits 0): GPU times cannot be measured";
  if (!(period_ns > 0.0f))
    return device + ": timestampPeriod is " + std::to_string(period_ns) + " ns: GPU times cannot be measured";
  return "";
}

// Of a physical device's queue family.
inline std::string timestamp_support_problem(VkPhysicalDevice physical_device, uint32_t queue_family_index) {
  VkPhysicalDeviceProperties properties{};
  vkGetPhysicalDeviceProperties(physical_device, &properties);
  uint32_t count = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(physical_device, &count, nullptr);
  std::vector<VkQueueFamilyProperties> families(count);
  vkGetPhysicalDeviceQueueFamilyProperties(physical_device, &count, families.data());
  const uint32_t bits = queue_family_index < count ? families[queue_family_index].timestampValidBits : 0u;
  return timestamp_support_problem(properties.deviceName, bits, properties.limits.timestampPeriod);
}

// Of two stamps written before and after recorded work, once it finished.
inline std::string timestamp_reading_problem(const std::string& device, uint64_t begin, uint64_t end) {
  if (begin == 0 && end == 0) return device + ": its timestamps read 0: GPU times cannot be measured";
  if (end <= begin)
    return device + ": a timestamp after the work (" + std::to_string(end) + ") is not past the one before it (" +
           std::to_string(begin) + "): GPU times cannot be measured";
  return "";
}

}  // namespace foveart::gpu_engine
