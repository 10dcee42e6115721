// In-process Vulkan validation for an instance of one's own (the GPU sample engine's
// CallbackAdapter, the tests' HeadlessVulkan): VK_LAYER_KHRONOS_validation with
// synchronization validation where the layer is installed, its error messages collected
// by a VkDebugUtilsMessengerEXT registered for the instance's whole life. (A messenger only
// chained into VkInstanceCreateInfo::pNext hears vkCreateInstance and vkDestroyInstance
// and nothing in between: the hazards of every submission would go unheard.)
// Header-only, so that test code uses it without the engine's library.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <mutex>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

namespace foveart::gpu_engine {

// The loader offers the instance layer `name`.
inline bool has_instance_layer(const char* name) {
  uint32_t count = 0;
  if (vkEnumerateInstanceLayerProperties(&count, nullptr) != VK_SUCCESS) return false;
  std::vector<VkLayerProperties> layers(count);
  if (vkEnumerateInstanceLayerProperties(&count, layers.data()) != VK_SUCCESS) return false;
  return std::any_of(layers.begin(), layers.end(), [&](const auto& l) { return std::strcmp(l.layerName, name) == 0; });
}

class ValidationMessenger {
 public:
  ValidationMessenger() = default;
  ValidationMessenger(const ValidationMessenger&) = delete;  // the messenger's user data is this object
  ValidationMessenger& operator=(const ValidationMessenger&) = delete;

  // With `validate` and the layer installed: enables the layer, VK_EXT_debug_utils and
  // synchronization validation in `info` (which enables no other layer or extension), with
  // the messenger in its pNext for vkCreateInstance itself. The structs chained are this
  // object's. False (`info` untouched) otherwise.
  bool chain(bool validate, VkInstanceCreateInfo* info) {
    if (!validate || !has_instance_layer(kLayer)) return false;
    messenger_info_.sType = VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT;
    messenger_info_.messageSeverity =
        VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT;
    messenger_info_.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT;
    messenger_info_.pfnUserCallback = on_message;
    messenger_info_.pUserData = this;
    features_.sType = VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT;
    features_.enabledValidationFeatureCount = 1;
    features_.pEnabledValidationFeatures = &kSynchronization;
    features_.pNext = &messenger_info_;
    features_chained_ = true;
    info->pNext = &features_;
    info->enabledLayerCount = 1;
    info->ppEnabledLayerNames = &kLayer;
    info->enabledExtensionCount = 1;
    info->ppEnabledExtensionNames = &kExtension;
    return true;
  }

  // After vkCreateInstance with a chained `info`: the messenger for the instance's life;
  // none (active() false) when the loader or the layer does not give one.
  void register_for(VkInstance instance) {
    if (!features_chained_) return;
    auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance, "vkCreateDebugUtilsMessengerEXT"));
    VkDebugUtilsMessengerCreateInfoEXT alone = messenger_info_;
    alone.pNext = nullptr;
    if (create == nullptr || create(instance, &alone, nullptr, &messenger_) != VK_SUCCESS) messenger_ = VK_NULL_HANDLE;
  }

  // Before vkDestroyInstance.
  void destroy(VkInstance instance) {
    if (messenger_ == VK_NULL_HANDLE) return;
    auto destroy_messenger = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance, "vkDestroyDebugUtilsMessengerEXT"));
    if (destroy_messenger != nullptr) destroy_messenger(instance, messenger_, nullptr);
    messenger_ = VK_NULL_HANDLE;
  }

  // Validation is on and a messenger hears it: errors() can report.
  bool active() const { return messenger_ != VK_NULL_HANDLE; }

  // The error messages heard so far, each "<message id name>: <message>" (the id, e.g.
  // SYNC-HAZARD-WRITE-AFTER-WRITE, is what a test looks for).
  std::vector<std::string> errors() const {
    std::lock_guard lock(mutex_);
    return errors_;
  }

 private:
  static constexpr const char* kLayer = "VK_LAYER_KHRONOS_validation";
  static constexpr const char* kExtension = VK_EXT_DEBUG_UTILS_EXTENSION_NAME;
  static constexpr VkValidationFeatureEnableEXT kSynchronization =
      VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT;

  // Called on any thread that calls Vulkan.
  static VKAPI_ATTR VkBool32 VKAPI_CALL on_message(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                   VkDebugUtilsMessageTypeFlagsEXT,
                                                   const VkDebugUtilsMessengerCallbackDataEXT* data, void* user) {
    if (severity >= VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT) {
      auto* self = static_cast<ValidationMessenger*>(user);
      std::string text = data->pMessageIdName != nullptr ? data->pMessageIdName : "?";
      text += ": ";
      text += data->pMessage != nullptr ? data->pMessage : "?";
      std::lock_guard lock(self->mutex_);
      self->errors_.push_back(std::move(text));
    }
    return VK_FALSE;
  }

  mutable std::mutex mutex_;
  std::vector<std::string> errors_;
  VkDebugUtilsMessengerCreateInfoEXT messenger_info_{};
  VkValidationFeaturesEXT features_{};
  bool features_chained_ = false;
  VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
};

}  // namespace foveart::gpu_engine
