// A Vulkan instance and device of its own, without OpenXR, for the GPU
// reconstruction's tests and benchmark (test code, not the layer's): one compute
// queue, the features the shaders need, and (optionally) VK_LAYER_KHRONOS_validation
// with synchronization validation, whose error messages it collects through a
// VkDebugUtilsMessengerEXT registered for the instance's whole life. (A messenger
// only chained into VkInstanceCreateInfo::pNext hears vkCreateInstance and
// vkDestroyInstance and nothing in between: the hazards of every submission
// would go unheard.)
#pragma once

#include <algorithm>
#include <cstring>
#include <functional>
#include <mutex>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "gpu/context.hpp"

namespace foveart::layer {
namespace headless_detail {

// The error messages heard; the callback may run on any thread that calls Vulkan.
struct Validation {
  std::mutex mutex;
  std::vector<std::string> errors;
};

// An error message as "<message id name>: <message>" (the id, e.g.
// SYNC-HAZARD-WRITE-AFTER-WRITE, is what a test looks for).
inline VKAPI_ATTR VkBool32 VKAPI_CALL on_message(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                          VkDebugUtilsMessageTypeFlagsEXT,
                                          const VkDebugUtilsMessengerCallbackDataEXT* data, void* user) {
  if (severity >= VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT) {
    auto* v = static_cast<Validation*>(user);
    std::string text = data->pMessageIdName != nullptr ? data->pMessageIdName : "?";
    text += ": ";
    text += data->pMessage != nullptr ? data->pMessage : "?";
    std::lock_guard lock(v->mutex);
    v->errors.push_back(std::move(text));
  }
  return VK_FALSE;
}

// The messenger's create info, for vkCreateDebugUtilsMessengerEXT and for the
// instance's pNext (which covers vkCreateInstance and vkDestroyInstance).
inline VkDebugUtilsMessengerCreateInfoEXT messenger_info(Validation* validation) {
  VkDebugUtilsMessengerCreateInfoEXT info{};
  info.sType = VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT;
  info.messageSeverity =
      VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT;
  info.messageType =
      VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT;
  info.pfnUserCallback = on_message;
  info.pUserData = validation;
  return info;
}

inline bool has_layer(const char* name) {
  uint32_t count = 0;
  vkEnumerateInstanceLayerProperties(&count, nullptr);
  std::vector<VkLayerProperties> layers(count);
  vkEnumerateInstanceLayerProperties(&count, layers.data());
  return std::any_of(layers.begin(), layers.end(), [&](const auto& l) { return std::strcmp(l.layerName, name) == 0; });
}

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
    const bool layer = validate && headless_detail::has_layer("VK_LAYER_KHRONOS_validation");
    VkApplicationInfo app{};
    app.sType = VK_STRUCTURE_TYPE_APPLICATION_INFO;
    app.pApplicationName = "gpu_reconstruction_test";
    app.apiVersion = VK_API_VERSION_1_1;
    const char* layers[] = {"VK_LAYER_KHRONOS_validation"};
    const char* extensions[] = {VK_EXT_DEBUG_UTILS_EXTENSION_NAME};
    VkValidationFeatureEnableEXT enables[] = {VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT};
    VkValidationFeaturesEXT features{};
    features.sType = VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT;
    features.enabledValidationFeatureCount = 1;
    features.pEnabledValidationFeatures = enables;
    VkDebugUtilsMessengerCreateInfoEXT messenger = headless_detail::messenger_info(&validation_);
    features.pNext = &messenger;
    VkInstanceCreateInfo info{};
    info.sType = VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO;
    info.pApplicationInfo = &app;
    if (layer) {
      info.pNext = &features;
      info.enabledLayerCount = 1;
      info.ppEnabledLayerNames = layers;
      info.enabledExtensionCount = 1;
      info.ppEnabledExtensionNames = extensions;
    }
    if (vkCreateInstance(&info, nullptr, &instance_) != VK_SUCCESS) return;
    if (layer) register_messenger(messenger);
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
    if (messenger_ != VK_NULL_HANDLE) {
      auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
          vkGetInstanceProcAddr(instance_, "vkDestroyDebugUtilsMessengerEXT"));
      if (destroy != nullptr) destroy(instance_, messenger_, nullptr);
    }
    if (instance_ != VK_NULL_HANDLE) vkDestroyInstance(instance_, nullptr);
  }
  bool ok() const { return device_ != VK_NULL_HANDLE; }
  // Validation is active: VK_LAYER_KHRONOS_validation is enabled with
  // synchronization validation and a messenger hears it (errors() can report).
  bool validated() const { return messenger_ != VK_NULL_HANDLE; }
  gpu::Device device() const { return {physical_, device_, family_, 0, false, {}}; }
  const std::string& name() const { return name_; }
  bool is_cpu() const { return type_ == VK_PHYSICAL_DEVICE_TYPE_CPU; }
  // The validation errors heard so far, each "<message id name>: <message>".
  std::vector<std::string> errors() {
    std::lock_guard lock(validation_.mutex);
    return validation_.errors;
  }

 private:
  void register_messenger(const VkDebugUtilsMessengerCreateInfoEXT& messenger) {
    auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance_, "vkCreateDebugUtilsMessengerEXT"));
    VkDebugUtilsMessengerCreateInfoEXT info = messenger;
    info.pNext = nullptr;
    if (create == nullptr || create(instance_, &info, nullptr, &messenger_) != VK_SUCCESS) messenger_ = VK_NULL_HANDLE;
  }

  headless_detail::Validation validation_;
  VkInstance instance_ = VK_NULL_HANDLE;
  VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
  VkPhysicalDevice physical_ = VK_NULL_HANDLE;
  VkDevice device_ = VK_NULL_HANDLE;
  uint32_t family_ = UINT32_MAX;
  VkPhysicalDeviceType type_ = VK_PHYSICAL_DEVICE_TYPE_OTHER;
  HeadlessVulkan(const HeadlessVulkan&) = delete;
  HeadlessVulkan& operator=(const HeadlessVulkan&) = delete;
  std::string name_;
};


}  // namespace foveart::layer
