// A minimal OpenXR + Vulkan application for the runtime tests: instance through
// the real loader, Vulkan through XR_KHR_vulkan_enable2, one session.
#pragma once

#include <vulkan/vulkan.h>

#include <map>
#include <string>
#include <vector>

#define XR_USE_GRAPHICS_API_VULKAN
#define XR_USE_TIMESPEC
#include <openxr/openxr.h>
#include <openxr/openxr_platform.h>
#include <time.h>

#include <gpu_engine/validation_messenger.hpp>

#include "sim_test_env.h"

namespace foveart::sim::test {

// A zeroed OpenXR struct with its type (and next) filled in.
template <class T>
T xr(XrStructureType type, void* next = nullptr) {
  T value{};
  value.type = type;
  value.next = next;
  return value;
}

class XrTestApp {
 public:
  XrTestApp() = default;
  XrTestApp(const XrTestApp&) = delete;
  XrTestApp& operator=(const XrTestApp&) = delete;
  ~XrTestApp();

  // extra: further extensions to enable (a layer's, for instance).
  XrResult create_instance(bool eye_gaze = true, const std::vector<const char*>& extra = {});
  // Vulkan instance/device through the runtime, then the session.
  XrResult create_session();
  // Polls events until the session reaches state (or max_polls frames pass);
  // runs empty frames while the session is running. Returns whether reached.
  bool run_until_state(XrSessionState state, int max_frames = 200);
  // Pops all queued events, recording session states.
  void drain_events();
  // One empty frame: wait, begin, end with no layers.
  XrResult empty_frame(XrFrameState* state_out = nullptr);
  template <class Fn>
  Fn proc(const char* name) {
    PFN_xrVoidFunction f = nullptr;
    xrGetInstanceProcAddr(instance, name, &f);
    return reinterpret_cast<Fn>(f);
  }

  XrInstance instance = XR_NULL_HANDLE;
  XrSystemId system = XR_NULL_SYSTEM_ID;
  XrSession session = XR_NULL_HANDLE;
  XrSessionState state = XR_SESSION_STATE_UNKNOWN;
  std::vector<XrSessionState> states;
  bool interaction_profile_changed = false;
  // What the VkInstance asks for (VkApplicationInfo::apiVersion), set before create_session.
  uint32_t vulkan_api_version = VK_API_VERSION_1_1;
  // Set before create_session: the VkInstance enables VK_LAYER_KHRONOS_validation with
  // synchronization validation where the loader offers it, heard for its whole life by `validation`.
  bool vulkan_validation = false;
  gpu_engine::ValidationMessenger validation;
  VkInstance vk_instance = VK_NULL_HANDLE;
  VkPhysicalDevice vk_physical = VK_NULL_HANDLE;
  VkDevice vk_device = VK_NULL_HANDLE;
  uint32_t queue_family = 0;

 private:
  XrResult create_vulkan_instance();
};

// The app's eye gaze: one pose action bound to /user/eyes_ext/input/gaze_ext/pose,
// attached, with an action space (EXPECTs every call).
struct GazeActions {
  XrActionSet set = XR_NULL_HANDLE;
  XrAction gaze = XR_NULL_HANDLE;
  XrSpace gaze_space = XR_NULL_HANDLE;
};
GazeActions make_gaze_actions(XrTestApp& app);
// xrSyncActions of that one set.
XrResult sync(XrTestApp& app, XrActionSet set);

}  // namespace foveart::sim::test
