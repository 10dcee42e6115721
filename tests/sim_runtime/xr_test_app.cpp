#include "xr_test_app.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>

namespace foveart::sim::test {

void set_env(const std::map<std::string, std::string>& vars) {
  for (const auto& [k, v] : vars) {
    if (v.empty())
      unsetenv(k.c_str());
    else
      setenv(k.c_str(), v.c_str(), 1);
  }
}

void clear_sim_env() {
  for (const char* k :
       {"FOVEART_SIM_FRAMES", "FOVEART_SIM_CLOCK", "FOVEART_SIM_GAZE", "FOVEART_SIM_EYE_TRACKING",
        "FOVEART_SIM_HEAD", "FOVEART_SIM_MOTION", "FOVEART_SIM_MOTION_SEED", "FOVEART_SIM_FORMATS",
        "FOVEART_SIM_CAPTURE_DIR", "FOVEART_SIM_CAPTURE_EVERY", "FOVEART_SIM_LOG",
        "XR_ENABLE_API_LAYERS", "VK_INSTANCE_LAYERS"}) {
    unsetenv(k);
  }
  setenv("XR_RUNTIME_JSON", FOVEART_SIM_RUNTIME_JSON, 1);
  setenv("FOVEART_SIM_LOG", "0", 1);
}

std::string fresh_dir(const std::string& name) {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::filesystem::path p = std::filesystem::path(FOVEART_TEST_TMP) /
                            (std::string(info->test_suite_name()) + "." + info->name()) / name;
  std::filesystem::remove_all(p);
  std::filesystem::create_directories(p);
  return p.string();
}

XrTestApp::~XrTestApp() {
  if (session != XR_NULL_HANDLE) xrDestroySession(session);
  if (vk_device != VK_NULL_HANDLE) vkDestroyDevice(vk_device, nullptr);
  if (vk_instance != VK_NULL_HANDLE) validation.destroy(vk_instance);
  if (vk_instance != VK_NULL_HANDLE) vkDestroyInstance(vk_instance, nullptr);
  if (instance != XR_NULL_HANDLE) xrDestroyInstance(instance);
}

XrResult XrTestApp::create_instance(bool eye_gaze, const std::vector<const char*>& extra) {
  std::vector<const char*> ext{XR_KHR_VULKAN_ENABLE2_EXTENSION_NAME,
                               XR_KHR_CONVERT_TIMESPEC_TIME_EXTENSION_NAME};
  if (eye_gaze) ext.push_back(XR_EXT_EYE_GAZE_INTERACTION_EXTENSION_NAME);
  ext.insert(ext.end(), extra.begin(), extra.end());
  XrInstanceCreateInfo info{};
  info.type = XR_TYPE_INSTANCE_CREATE_INFO;
  std::snprintf(info.applicationInfo.applicationName, XR_MAX_APPLICATION_NAME_SIZE,
                "sim_runtime_tests");
  info.applicationInfo.apiVersion = XR_CURRENT_API_VERSION;
  info.enabledExtensionCount = static_cast<uint32_t>(ext.size());
  info.enabledExtensionNames = ext.data();
  XrResult r = xrCreateInstance(&info, &instance);
  if (XR_FAILED(r)) return r;
  XrSystemGetInfo sys{};
  sys.type = XR_TYPE_SYSTEM_GET_INFO;
  sys.formFactor = XR_FORM_FACTOR_HEAD_MOUNTED_DISPLAY;
  return xrGetSystem(instance, &sys, &system);
}

// The VkInstance through xrCreateVulkanInstanceKHR, validated where vulkan_validation asks.
XrResult XrTestApp::create_vulkan_instance() {
  auto create_vk_instance = proc<PFN_xrCreateVulkanInstanceKHR>("xrCreateVulkanInstanceKHR");
  if (!create_vk_instance) return XR_ERROR_FUNCTION_UNSUPPORTED;
  VkApplicationInfo app{};
  app.sType = VK_STRUCTURE_TYPE_APPLICATION_INFO;
  app.pApplicationName = "sim_runtime_tests";
  app.apiVersion = vulkan_api_version;
  VkInstanceCreateInfo vk_info{};
  vk_info.sType = VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO;
  vk_info.pApplicationInfo = &app;
  validation.chain(vulkan_validation, &vk_info);
  XrVulkanInstanceCreateInfoKHR xr_vk{};
  xr_vk.type = XR_TYPE_VULKAN_INSTANCE_CREATE_INFO_KHR;
  xr_vk.systemId = system;
  xr_vk.pfnGetInstanceProcAddr = &vkGetInstanceProcAddr;
  xr_vk.vulkanCreateInfo = &vk_info;
  VkResult vr = VK_SUCCESS;
  if (XrResult r = create_vk_instance(instance, &xr_vk, &vk_instance, &vr); XR_FAILED(r) || vr != VK_SUCCESS) {
    return XR_FAILED(r) ? r : XR_ERROR_RUNTIME_FAILURE;
  }
  validation.register_for(vk_instance);
  return XR_SUCCESS;
}

XrResult XrTestApp::create_session() {
  auto get_req =
      proc<PFN_xrGetVulkanGraphicsRequirements2KHR>("xrGetVulkanGraphicsRequirements2KHR");
  auto get_device = proc<PFN_xrGetVulkanGraphicsDevice2KHR>("xrGetVulkanGraphicsDevice2KHR");
  auto create_vk_device = proc<PFN_xrCreateVulkanDeviceKHR>("xrCreateVulkanDeviceKHR");
  if (!get_req || !get_device || !create_vk_device)
    return XR_ERROR_FUNCTION_UNSUPPORTED;
  XrGraphicsRequirementsVulkan2KHR req{};
  req.type = XR_TYPE_GRAPHICS_REQUIREMENTS_VULKAN2_KHR;
  if (XrResult r = get_req(instance, system, &req); XR_FAILED(r)) return r;
  if (XrResult r = create_vulkan_instance(); XR_FAILED(r)) return r;
  VkResult vr = VK_SUCCESS;
  XrVulkanGraphicsDeviceGetInfoKHR dev_info{};
  dev_info.type = XR_TYPE_VULKAN_GRAPHICS_DEVICE_GET_INFO_KHR;
  dev_info.systemId = system;
  dev_info.vulkanInstance = vk_instance;
  if (XrResult r = get_device(instance, &dev_info, &vk_physical); XR_FAILED(r)) return r;

  uint32_t n = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(vk_physical, &n, nullptr);
  std::vector<VkQueueFamilyProperties> families(n);
  vkGetPhysicalDeviceQueueFamilyProperties(vk_physical, &n, families.data());
  for (uint32_t i = 0; i < n; ++i) {
    if (families[i].queueFlags & VK_QUEUE_GRAPHICS_BIT) {
      queue_family = i;
      break;
    }
  }
  const float priority = 1.0F;
  VkDeviceQueueCreateInfo queue{};
  queue.sType = VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO;
  queue.queueFamilyIndex = queue_family;
  queue.queueCount = 1;
  queue.pQueuePriorities = &priority;
  VkDeviceCreateInfo device_info{};
  device_info.sType = VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO;
  device_info.queueCreateInfoCount = 1;
  device_info.pQueueCreateInfos = &queue;
  XrVulkanDeviceCreateInfoKHR xr_dev{};
  xr_dev.type = XR_TYPE_VULKAN_DEVICE_CREATE_INFO_KHR;
  xr_dev.systemId = system;
  xr_dev.pfnGetInstanceProcAddr = &vkGetInstanceProcAddr;
  xr_dev.vulkanPhysicalDevice = vk_physical;
  xr_dev.vulkanCreateInfo = &device_info;
  if (XrResult r = create_vk_device(instance, &xr_dev, &vk_device, &vr);
      XR_FAILED(r) || vr != VK_SUCCESS) {
    return XR_FAILED(r) ? r : XR_ERROR_RUNTIME_FAILURE;
  }

  XrGraphicsBindingVulkan2KHR binding{};
  binding.type = XR_TYPE_GRAPHICS_BINDING_VULKAN2_KHR;
  binding.instance = vk_instance;
  binding.physicalDevice = vk_physical;
  binding.device = vk_device;
  binding.queueFamilyIndex = queue_family;
  binding.queueIndex = 0;
  XrSessionCreateInfo session_info{};
  session_info.type = XR_TYPE_SESSION_CREATE_INFO;
  session_info.next = &binding;
  session_info.systemId = system;
  return xrCreateSession(instance, &session_info, &session);
}

void XrTestApp::drain_events() {
  XrEventDataBuffer event{};
  event.type = XR_TYPE_EVENT_DATA_BUFFER;
  while (xrPollEvent(instance, &event) == XR_SUCCESS) {
    if (event.type == XR_TYPE_EVENT_DATA_SESSION_STATE_CHANGED) {
      state = reinterpret_cast<XrEventDataSessionStateChanged*>(&event)->state;
      states.push_back(state);
      if (state == XR_SESSION_STATE_READY) {
        XrSessionBeginInfo begin{};
        begin.type = XR_TYPE_SESSION_BEGIN_INFO;
        begin.primaryViewConfigurationType = XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO;
        EXPECT_EQ(xrBeginSession(session, &begin), XR_SUCCESS);
      } else if (state == XR_SESSION_STATE_STOPPING) {
        EXPECT_EQ(xrEndSession(session), XR_SUCCESS);
      }
    } else if (event.type == XR_TYPE_EVENT_DATA_INTERACTION_PROFILE_CHANGED) {
      interaction_profile_changed = true;
    }
    event = XrEventDataBuffer{};
    event.type = XR_TYPE_EVENT_DATA_BUFFER;
  }
}

XrResult XrTestApp::empty_frame(XrFrameState* state_out) {
  XrFrameWaitInfo wait{};
  wait.type = XR_TYPE_FRAME_WAIT_INFO;
  XrFrameState frame{};
  frame.type = XR_TYPE_FRAME_STATE;
  if (XrResult r = xrWaitFrame(session, &wait, &frame); XR_FAILED(r)) return r;
  XrFrameBeginInfo begin{};
  begin.type = XR_TYPE_FRAME_BEGIN_INFO;
  if (XrResult r = xrBeginFrame(session, &begin); XR_FAILED(r)) return r;
  XrFrameEndInfo end{};
  end.type = XR_TYPE_FRAME_END_INFO;
  end.displayTime = frame.predictedDisplayTime;
  end.environmentBlendMode = XR_ENVIRONMENT_BLEND_MODE_OPAQUE;
  if (state_out != nullptr) *state_out = frame;
  return xrEndFrame(session, &end);
}

bool XrTestApp::run_until_state(XrSessionState target, int max_frames) {
  for (int i = 0; i < max_frames; ++i) {
    drain_events();
    if (state == target) return true;
    if (state == XR_SESSION_STATE_EXITING) return false;
    const bool running = state == XR_SESSION_STATE_READY ||
                         state == XR_SESSION_STATE_SYNCHRONIZED ||
                         state == XR_SESSION_STATE_VISIBLE || state == XR_SESSION_STATE_FOCUSED ||
                         state == XR_SESSION_STATE_STOPPING;
    if (running && XR_FAILED(empty_frame())) return false;
  }
  drain_events();
  return state == target;
}

GazeActions make_gaze_actions(XrTestApp& app) {
  GazeActions g;
  auto set_info = xr<XrActionSetCreateInfo>(XR_TYPE_ACTION_SET_CREATE_INFO);
  std::snprintf(set_info.actionSetName, sizeof set_info.actionSetName, "gaze");
  std::snprintf(set_info.localizedActionSetName, sizeof set_info.localizedActionSetName, "Gaze");
  EXPECT_EQ(xrCreateActionSet(app.instance, &set_info, &g.set), XR_SUCCESS);
  auto action_info = xr<XrActionCreateInfo>(XR_TYPE_ACTION_CREATE_INFO);
  action_info.actionType = XR_ACTION_TYPE_POSE_INPUT;
  std::snprintf(action_info.actionName, sizeof action_info.actionName, "gaze_pose");
  std::snprintf(action_info.localizedActionName, sizeof action_info.localizedActionName,
                "Gaze pose");
  EXPECT_EQ(xrCreateAction(g.set, &action_info, &g.gaze), XR_SUCCESS);
  XrPath profile = XR_NULL_PATH;
  XrPath binding = XR_NULL_PATH;
  EXPECT_EQ(
      xrStringToPath(app.instance, "/interaction_profiles/ext/eye_gaze_interaction", &profile),
      XR_SUCCESS);
  EXPECT_EQ(xrStringToPath(app.instance, "/user/eyes_ext/input/gaze_ext/pose", &binding),
            XR_SUCCESS);
  XrActionSuggestedBinding suggested{g.gaze, binding};
  auto suggest =
      xr<XrInteractionProfileSuggestedBinding>(XR_TYPE_INTERACTION_PROFILE_SUGGESTED_BINDING);
  suggest.interactionProfile = profile;
  suggest.countSuggestedBindings = 1;
  suggest.suggestedBindings = &suggested;
  EXPECT_EQ(xrSuggestInteractionProfileBindings(app.instance, &suggest), XR_SUCCESS);
  auto attach = xr<XrSessionActionSetsAttachInfo>(XR_TYPE_SESSION_ACTION_SETS_ATTACH_INFO);
  attach.countActionSets = 1;
  attach.actionSets = &g.set;
  EXPECT_EQ(xrAttachSessionActionSets(app.session, &attach), XR_SUCCESS);
  auto space_info = xr<XrActionSpaceCreateInfo>(XR_TYPE_ACTION_SPACE_CREATE_INFO);
  space_info.action = g.gaze;
  space_info.poseInActionSpace.orientation.w = 1.0F;
  EXPECT_EQ(xrCreateActionSpace(app.session, &space_info, &g.gaze_space), XR_SUCCESS);
  return g;
}

XrResult sync(XrTestApp& app, XrActionSet set) {
  XrActiveActionSet active{set, XR_NULL_PATH};
  auto info = xr<XrActionsSyncInfo>(XR_TYPE_ACTIONS_SYNC_INFO);
  info.countActiveActionSets = 1;
  info.activeActionSets = &active;
  return xrSyncActions(app.session, &info);
}

}  // namespace foveart::sim::test
