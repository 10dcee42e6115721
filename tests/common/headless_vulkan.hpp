// A Vulkan instance and device of its own, without OpenXR, for the GPU
// reconstruction's tests and benchmark (test code, not the layer's): one compute
// queue, the features the shaders need, and (optionally) VK_LAYER_KHRONOS_validation
// with synchronization validation, whose error messages it collects
// (gpu_engine::ValidationMessenger, as the GPU sample engine's adapter does).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "gpu/context.hpp"
#include "gpu_engine/validation_messenger.hpp"

namespace foveart::layer {
namespace headless_detail {

// Lower is preferred.
inline int device_rank(VkPhysicalDeviceType type, bool prefer_cpu) {
  if (prefer_cpu) return type == VK_PHYSICAL_DEVICE_TYPE_CPU ? 0 : 1;
  switch (type) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return 0;
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return 1;
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return 2;
    default: return 3;
  }
}

}  // namespace headless_detail

// Which device a HeadlessVulkan takes when a machine has several.
enum class DevicePreference {
  hardware_gpu,  // a discrete GPU, else an integrated one, else a virtual one, else whatever there is
  cpu,           // a CPU implementation (lavapipe), else whatever there is
};

// Called with the chosen physical device and the VkDeviceCreateInfo just before
// vkCreateDevice: may add extensions and feature structs (which must outlive the
// call), e.g. gpu_engine::RayTracingDeviceSupport::enable.
using DeviceCreateHook = std::function<void(VkPhysicalDevice, VkDeviceCreateInfo*)>;

// The name of the device DevicePreference::hardware_gpu would take, when that is
// a GPU (discrete, integrated or virtual) and not a CPU implementation such as
// lavapipe; empty without one. A plain instance, no validation, no device.
// `while_loaded` runs before the instance is destroyed, while the loader still
// holds the drivers (icd_pin.h).
inline std::string hardware_gpu_name(const std::function<void()>& while_loaded = {}) {
  VkApplicationInfo app{};
  app.sType = VK_STRUCTURE_TYPE_APPLICATION_INFO;
  app.pApplicationName = "hardware_gpu_probe";
  app.apiVersion = VK_API_VERSION_1_1;
  VkInstanceCreateInfo info{};
  info.sType = VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO;
  info.pApplicationInfo = &app;
  VkInstance instance = VK_NULL_HANDLE;
  if (vkCreateInstance(&info, nullptr, &instance) != VK_SUCCESS) return {};
  uint32_t count = 0;
  vkEnumeratePhysicalDevices(instance, &count, nullptr);
  std::vector<VkPhysicalDevice> devices(count);
  vkEnumeratePhysicalDevices(instance, &count, devices.data());
  std::string name;
  int best = 3;  // headless_detail::device_rank: 0-2 are GPUs
  for (VkPhysicalDevice d : devices) {
    VkPhysicalDeviceProperties p{};
    vkGetPhysicalDeviceProperties(d, &p);
    const int rank = headless_detail::device_rank(p.deviceType, false);
    if (rank < best) {
      best = rank;
      name = p.deviceName;
    }
  }
  if (while_loaded) while_loaded();
  vkDestroyInstance(instance, nullptr);
  return name;
}

class HeadlessVulkan {
 public:
  // The device `preference` ranks first; validated (when the layer is installed)
  // with synchronization validation on.
  HeadlessVulkan(DevicePreference preference, bool validate, const DeviceCreateHook& before_create_device = {}) {
    VkApplicationInfo app{};
    app.sType = VK_STRUCTURE_TYPE_APPLICATION_INFO;
    app.pApplicationName = "gpu_reconstruction_test";
    app.apiVersion = VK_API_VERSION_1_1;
    VkInstanceCreateInfo info{};
    info.sType = VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO;
    info.pApplicationInfo = &app;
    validation_.chain(validate, &info);
    if (vkCreateInstance(&info, nullptr, &instance_) != VK_SUCCESS) return;
    validation_.register_for(instance_);
    uint32_t count = 0;
    vkEnumeratePhysicalDevices(instance_, &count, nullptr);
    std::vector<VkPhysicalDevice> devices(count);
    vkEnumeratePhysicalDevices(instance_, &count, devices.data());
    const bool prefer_cpu = preference == DevicePreference::cpu;
    for (VkPhysicalDevice d : devices) {
      VkPhysicalDeviceProperties p{};
      vkGetPhysicalDeviceProperties(d, &p);
      if (physical_ == VK_NULL_HANDLE ||
          headless_detail::device_rank(p.deviceType, prefer_cpu) < headless_detail::device_rank(type_, prefer_cpu)) {
        physical_ = d;
        name_ = p.deviceName;
        type_ = p.deviceType;
      }
    }
    if (physical_ == VK_NULL_HANDLE) return;
    vkGetPhysicalDeviceQueueFamilyProperties(physical_, &count, nullptr);
    std::vector<VkQueueFamilyProperties> families(count);
    vkGetPhysicalDeviceQueueFamilyProperties(physical_, &count, families.data());
    for (uint32_t i = 0; i < count && family_ == UINT32_MAX; ++i)
      if (families[i].queueFlags & VK_QUEUE_COMPUTE_BIT) family_ = i;
    const float priority = 1.0f;
    VkDeviceQueueCreateInfo queue{};
    queue.sType = VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO;
    queue.queueFamilyIndex = family_;
    queue.queueCount = 1;
    queue.pQueuePriorities = &priority;
    VkPhysicalDeviceFeatures enabled{};
    enabled.shaderStorageBufferArrayDynamicIndexing = VK_TRUE;
    VkDeviceCreateInfo device_info{};
    device_info.sType = VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO;
    device_info.queueCreateInfoCount = 1;
    device_info.pQueueCreateInfos = &queue;
    device_info.pEnabledFeatures = &enabled;
    if (before_create_device) before_create_device(physical_, &device_info);
    if (vkCreateDevice(physical_, &device_info, nullptr, &device_) != VK_SUCCESS) device_ = VK_NULL_HANDLE;
  }
  ~HeadlessVulkan() {
    if (device_ != VK_NULL_HANDLE) vkDeviceWaitIdle(device_);
    if (device_ != VK_NULL_HANDLE) vkDestroyDevice(device_, nullptr);
    validation_.destroy(instance_);
    if (instance_ != VK_NULL_HANDLE) vkDestroyInstance(instance_, nullptr);
  }
  bool ok() const { return device_ != VK_NULL_HANDLE; }
  // Validation is active: VK_LAYER_KHRONOS_validation is enabled with
  // synchronization validation and a messenger hears it (errors() can report).
  bool validated() const { return validation_.active(); }
  gpu::Device device() const { return {physical_, device_, family_, 0, false, {}}; }
  const std::string& name() const { return name_; }
  bool is_cpu() const { return type_ == VK_PHYSICAL_DEVICE_TYPE_CPU; }
  // The validation errors heard so far, each "<message id name>: <message>".
  std::vector<std::string> errors() const { return validation_.errors(); }

 private:
  gpu_engine::ValidationMessenger validation_;
  VkInstance instance_ = VK_NULL_HANDLE;
  VkPhysicalDevice physical_ = VK_NULL_HANDLE;
  VkDevice device_ = VK_NULL_HANDLE;
  uint32_t family_ = UINT32_MAX;
  VkPhysicalDeviceType type_ = VK_PHYSICAL_DEVICE_TYPE_OTHER;
  HeadlessVulkan(const HeadlessVulkan&) = delete;
  HeadlessVulkan& operator=(const HeadlessVulkan&) = delete;
  std::string name_;
};


}  // namespace foveart::layer
