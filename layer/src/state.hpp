// What the layer remembers, keyed by handle: instances, sessions and
// foveated renderers. One registry behind one mutex; hooks copy out a
// shared_ptr and release the lock before calling down the chain.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <mutex>
#include <string>
#include <unordered_map>
#include <vector>

#include "config.hpp"
#include "dispatch.hpp"
#include "eye_gaze.hpp"
#include "layer/XR_FOVEART_foveated_ray_tracing.h"

namespace foveart::layer {

class FoveatedRenderer;

// What the app enabled on its VkDevice that the layer's device work may use
// (recorded at xrCreateVulkanDeviceKHR: vulkan_device.hpp).
struct VulkanDeviceFeatures {
  bool buffer_device_address = false;  // bufferDeviceAddress: the device trace's buffers get addresses
  bool timeline_semaphore = false;     // timelineSemaphore
};

struct InstanceState {
  XrInstance handle = XR_NULL_HANDLE;
  NextDispatch next;
  LayerConfig config;
  std::string application_name;
  bool extension_enabled = false;  // the app enabled XR_FOVEART_foveated_ray_tracing
  bool vulkan2_enabled = false;    // ... and XR_KHR_vulkan_enable2
  bool eye_gaze_enabled = false;   // ... and XR_EXT_eye_gaze_interaction
  EyeGazeActions eye_gaze;         // the layer's own gaze action (ready() when usable)
};

struct SessionState {
  XrSession handle = XR_NULL_HANDLE;
  XrSystemId system_id = XR_NULL_SYSTEM_ID;
  std::shared_ptr<InstanceState> instance;
  bool has_vulkan = false;  // the session was created with a Vulkan graphics binding
  VkInstance vk_instance = VK_NULL_HANDLE;
  uint32_t vk_instance_api_version = 0;  // what vk_instance asked for at xrCreateVulkanInstanceKHR; 0: unknown
  VkPhysicalDevice vk_physical_device = VK_NULL_HANDLE;
  VkDevice vk_device = VK_NULL_HANDLE;
  uint32_t vk_queue_family_index = 0;
  uint32_t vk_queue_index = 0;
  // What the app enabled on vk_device through xrCreateVulkanDeviceKHR (false otherwise).
  bool buffer_device_address = false;
  bool timeline_semaphore = false;
  std::shared_ptr<SessionEyeGaze> eye_gaze;  // null unless the instance's eye_gaze is ready()
};

// The size of an app swapchain, recorded at xrCreateSwapchain: what an
// imageRect is checked against.
struct SwapchainExtent {
  XrSession session = XR_NULL_HANDLE;
  uint32_t width_px = 0;
  uint32_t height_px = 0;
  uint32_t array_size = 0;
};

class Registry {
 public:
  static Registry& get();

  void add_instance(std::shared_ptr<InstanceState> state);
  std::shared_ptr<InstanceState> instance(XrInstance handle) const;
  // Removes the instance with its sessions and renderers; returns the renderers
  // so the caller can destroy them outside the lock.
  std::vector<std::shared_ptr<FoveatedRenderer>> remove_instance(XrInstance handle);

  void add_session(std::shared_ptr<SessionState> state);
  std::shared_ptr<SessionState> session(XrSession handle) const;
  std::vector<std::shared_ptr<FoveatedRenderer>> remove_session(XrSession handle);

  XrFoveatedRendererFOVEART add_renderer(XrSession session, std::shared_ptr<FoveatedRenderer> renderer);
  std::shared_ptr<FoveatedRenderer> renderer(XrFoveatedRendererFOVEART handle) const;
  // The renderer if it belongs to `session`; null otherwise, with *out_foreign
  // set (and the renderer in *out_other) when it exists but belongs to another session.
  std::shared_ptr<FoveatedRenderer> renderer_of_session(XrFoveatedRendererFOVEART handle, XrSession session,
                                                        std::shared_ptr<FoveatedRenderer>* out_other) const;
  std::shared_ptr<FoveatedRenderer> remove_renderer(XrFoveatedRendererFOVEART handle);
  bool session_has_renderers(XrSession session) const;

  void add_swapchain(XrSwapchain handle, const SwapchainExtent& extent);
  void remove_swapchain(XrSwapchain handle);
  // The next link's xrDestroySwapchain for an app swapchain; null when unknown.
  PFN_xrDestroySwapchain destroy_swapchain_function(XrSwapchain handle) const;
  // The app swapchain's extent if it was created in `session`.
  std::optional<SwapchainExtent> swapchain(XrSwapchain handle, XrSession session) const;

  // The Vulkan version an instance created through xrCreateVulkanInstanceKHR asked for; 0 for another instance.
  void add_vulkan_instance(XrInstance instance, VkInstance vulkan_instance, uint32_t api_version);
  uint32_t vulkan_instance_api_version(VkInstance vulkan_instance) const;
  // The features a device created through xrCreateVulkanDeviceKHR enabled; none for another device.
  void add_vulkan_device(XrInstance instance, VkDevice device, const VulkanDeviceFeatures& features);
  VulkanDeviceFeatures vulkan_device(VkDevice device) const;

  std::size_t instance_count() const;

 private:
  struct RendererEntry {
    XrSession session;
    std::shared_ptr<FoveatedRenderer> renderer;
  };
  struct VulkanDeviceEntry {
    XrInstance instance;
    VulkanDeviceFeatures features;
  };
  struct VulkanInstanceEntry {
    XrInstance instance;
    uint32_t api_version;
  };
  // Moves the session's renderers into *removed and forgets its swapchains;
  // the caller holds mutex_ and erases the session itself.
  void erase_children_of_session(XrSession session, std::vector<std::shared_ptr<FoveatedRenderer>>* removed);

  mutable std::mutex mutex_;
  std::unordered_map<XrInstance, std::shared_ptr<InstanceState>> instances_;
  std::unordered_map<XrSession, std::shared_ptr<SessionState>> sessions_;
  std::unordered_map<uint64_t, RendererEntry> renderers_;
  std::unordered_map<XrSwapchain, SwapchainExtent> swapchains_;
  std::unordered_map<VkDevice, VulkanDeviceEntry> vulkan_devices_;
  std::unordered_map<VkInstance, VulkanInstanceEntry> vulkan_instances_;
  uint64_t next_renderer_id_ = 1;
};

}  // namespace foveart::layer
