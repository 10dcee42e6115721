#include "xr_app.hpp"

#include "app_trace.hpp"
#include "command_pool.hpp"
#include <gpu_engine/rt_device.hpp>

#include <array>
#include <chrono>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <vector>

namespace foveart::hello {
namespace {

// Throws with the call and the result; run_app turns it into AppResult::error.
void check(XrResult r, const char* what) {
  if (XR_FAILED(r)) throw std::runtime_error(std::string(what) + " failed: XrResult " + std::to_string(r));
}
void check(VkResult r, const char* what) {
  if (r != VK_SUCCESS) throw std::runtime_error(std::string(what) + " failed: VkResult " + std::to_string(r));
}

template <class T>
T xr_struct(XrStructureType type) {
  T s{};
  s.type = type;
  return s;
}
template <class T>
T vk_struct(VkStructureType type) {
  T s{};
  s.sType = type;
  return s;
}

template <class Fn>
Fn proc(XrInstance instance, const char* name) {
  PFN_xrVoidFunction fn = nullptr;
  check(xrGetInstanceProcAddr(instance, name, &fn), name);
  return reinterpret_cast<Fn>(fn);
}

XrQuaternionf conjugate(XrQuaternionf q) { return {-q.x, -q.y, -q.z, q.w}; }

XrVector3f rotate(XrQuaternionf q, XrVector3f v) {
  // v' = v + 2 w (u x v) + 2 u x (u x v), u = (x, y, z)
  const XrVector3f u{q.x, q.y, q.z};
  const XrVector3f t{2 * (u.y * v.z - u.z * v.y), 2 * (u.z * v.x - u.x * v.z), 2 * (u.x * v.y - u.y * v.x)};
  return {v.x + q.w * t.x + (u.y * t.z - u.z * t.y), v.y + q.w * t.y + (u.z * t.x - u.x * t.z),
          v.z + q.w * t.z + (u.x * t.y - u.y * t.x)};
}

XrPosef inverse(const XrPosef& p) {
  const XrQuaternionf qi = conjugate(p.orientation);
  const XrVector3f t = rotate(qi, p.position);
  return {qi, {-t.x, -t.y, -t.z}};
}

struct EyeSwapchain {
  XrSwapchain handle = XR_NULL_HANDLE;
  std::vector<VkImage> images;
  int32_t width = 0, height = 0;
};

class App {
 public:
  explicit App(const AppOptions& options) : options_(options) {}
  ~App() { shutdown(); }

  AppResult run() {
    create_instance();
    create_vulkan();
    create_session();
    if (options_.app_actions) create_app_actions();
    create_swapchains();
    create_device_trace();
    create_view_renderer();
    create_renderer();
    AppResult result;
    loop(&result);
    result.ok = true;
    result.frames = frames_;
    result.stats = xr_struct<XrFoveatedRendererStatsFOVEART>(XR_TYPE_FOVEATED_RENDERER_STATS_FOVEART);
    result.reconstruction = xr_struct<XrFoveatedRendererReconstructionStatsFOVEART>(
        XR_TYPE_FOVEATED_RENDERER_RECONSTRUCTION_STATS_FOVEART);
    result.stats.next = &result.reconstruction;
    result.app_trace = xr_struct<XrFoveatedAppTraceStatsFOVEART>(XR_TYPE_FOVEATED_APP_TRACE_STATS_FOVEART);
    result.reconstruction.next = &result.app_trace;
    result.density = xr_struct<XrFoveatedRendererDensityStatsFOVEART>(XR_TYPE_FOVEATED_RENDERER_DENSITY_STATS_FOVEART);
    result.app_trace.next = &result.density;
    check(get_stats_(renderer_, &result.stats), "xrGetFoveatedRendererStatsFOVEART");
    result.stats.next = nullptr;
    result.reconstruction.next = nullptr;
    result.app_trace.next = nullptr;
    result.second_queue = trace_queue_ != queue_;
    return result;
  }

 private:
  void create_instance() {
    std::vector<const char*> layers;
    if (options_.enable_layer) layers.push_back(XR_FOVEART_API_LAYER_NAME);
    std::vector<const char*> extensions{XR_KHR_VULKAN_ENABLE2_EXTENSION_NAME,
                                        XR_FOVEART_FOVEATED_RAY_TRACING_EXTENSION_NAME};
    if (options_.app_actions) extensions.push_back(XR_EXT_EYE_GAZE_INTERACTION_EXTENSION_NAME);
    auto info = xr_struct<XrInstanceCreateInfo>(XR_TYPE_INSTANCE_CREATE_INFO);
    std::strncpy(info.applicationInfo.applicationName, "hello_foveated", XR_MAX_APPLICATION_NAME_SIZE - 1);
    std::strncpy(info.applicationInfo.engineName, "foveart_engine", XR_MAX_ENGINE_NAME_SIZE - 1);
    info.applicationInfo.apiVersion = XR_CURRENT_API_VERSION;
    info.enabledApiLayerCount = static_cast<uint32_t>(layers.size());
    info.enabledApiLayerNames = layers.data();
    info.enabledExtensionCount = static_cast<uint32_t>(extensions.size());
    info.enabledExtensionNames = extensions.data();
    const XrResult created = xrCreateInstance(&info, &instance_);
    const bool layer_missing = created == XR_ERROR_API_LAYER_NOT_PRESENT || created == XR_ERROR_EXTENSION_NOT_PRESENT;
    check(created, layer_missing ? "xrCreateInstance (is the FoveaRT layer installed? XR_API_LAYER_PATH names the "
                                   "folder of its manifest)"
                                 : "xrCreateInstance");
    auto system_info = xr_struct<XrSystemGetInfo>(XR_TYPE_SYSTEM_GET_INFO);
    system_info.formFactor = XR_FORM_FACTOR_HEAD_MOUNTED_DISPLAY;
    check(xrGetSystem(instance_, &system_info, &system_), "xrGetSystem");
    create_renderer_ = proc<PFN_xrCreateFoveatedRendererFOVEART>(instance_, "xrCreateFoveatedRendererFOVEART");
    destroy_renderer_ = proc<PFN_xrDestroyFoveatedRendererFOVEART>(instance_, "xrDestroyFoveatedRendererFOVEART");
    get_stats_ = proc<PFN_xrGetFoveatedRendererStatsFOVEART>(instance_, "xrGetFoveatedRendererStatsFOVEART");
    if (options_.app_recorded_trace) {
      acquire_batch_ = proc<PFN_xrAcquireFoveatedRayBatchFOVEART>(instance_, "xrAcquireFoveatedRayBatchFOVEART");
      release_batch_ = proc<PFN_xrReleaseFoveatedRayBatchFOVEART>(instance_, "xrReleaseFoveatedRayBatchFOVEART");
    }
  }

  void create_vulkan() {
    auto requirements = xr_struct<XrGraphicsRequirementsVulkan2KHR>(XR_TYPE_GRAPHICS_REQUIREMENTS_VULKAN2_KHR);
    check(proc<PFN_xrGetVulkanGraphicsRequirements2KHR>(instance_, "xrGetVulkanGraphicsRequirements2KHR")(
              instance_, system_, &requirements),
          "xrGetVulkanGraphicsRequirements2KHR");
    auto app = vk_struct<VkApplicationInfo>(VK_STRUCTURE_TYPE_APPLICATION_INFO);
    app.pApplicationName = "hello_foveated";
    uint32_t loader_version = VK_API_VERSION_1_0;
    vkEnumerateInstanceVersion(&loader_version);
    // 1.2 where the loader has it (the device's features: create_device), else 1.1 as the engines need.
    app.apiVersion = loader_version >= VK_API_VERSION_1_2 ? VK_API_VERSION_1_2 : VK_API_VERSION_1_1;
    instance_api_version_ = app.apiVersion;
    auto vk_info = vk_struct<VkInstanceCreateInfo>(VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO);
    vk_info.pApplicationInfo = &app;
    auto create = xr_struct<XrVulkanInstanceCreateInfoKHR>(XR_TYPE_VULKAN_INSTANCE_CREATE_INFO_KHR);
    create.systemId = system_;
    create.pfnGetInstanceProcAddr = &vkGetInstanceProcAddr;
    create.vulkanCreateInfo = &vk_info;
    VkResult vr = VK_SUCCESS;
    check(proc<PFN_xrCreateVulkanInstanceKHR>(instance_, "xrCreateVulkanInstanceKHR")(instance_, &create,
                                                                                      &vk_instance_, &vr),
          "xrCreateVulkanInstanceKHR");
    check(vr, "vkCreateInstance");
    auto device_get = xr_struct<XrVulkanGraphicsDeviceGetInfoKHR>(XR_TYPE_VULKAN_GRAPHICS_DEVICE_GET_INFO_KHR);
    device_get.systemId = system_;
    device_get.vulkanInstance = vk_instance_;
    check(proc<PFN_xrGetVulkanGraphicsDevice2KHR>(instance_, "xrGetVulkanGraphicsDevice2KHR")(instance_, &device_get,
                                                                                              &physical_device_),
          "xrGetVulkanGraphicsDevice2KHR");
    uint32_t family_count = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(physical_device_, &family_count, nullptr);
    std::vector<VkQueueFamilyProperties> families(family_count);
    vkGetPhysicalDeviceQueueFamilyProperties(physical_device_, &family_count, families.data());
    queue_family_ = UINT32_MAX;
    for (uint32_t i = 0; i < family_count; ++i) {
      if (families[i].queueFlags & VK_QUEUE_GRAPHICS_BIT) {
        queue_family_ = i;
        break;
      }
    }
    if (queue_family_ == UINT32_MAX) throw std::runtime_error("no graphics queue family");
    // The app-recorded trace traces on a second queue of the family where it has one (lavapipe has one queue).
    queue_count_ = options_.app_recorded_trace && families[queue_family_].queueCount >= 2 ? 2 : 1;
    create_device();
    vkGetDeviceQueue(device_, queue_family_, 0, &queue_);
    vkGetDeviceQueue(device_, queue_family_, queue_count_ - 1, &trace_queue_);
    placeholder_.create(device_, queue_family_, 1, "placeholder clear");
  }

  // The device through the runtime, with one valid feature chain: on Vulkan 1.2 (instance and device)
  // one VkPhysicalDeviceVulkan12Features with bufferDeviceAddress (the device trace's addresses) and
  // timelineSemaphore where offered; the ray-tracing pipeline's extensions and features where offered.
  void create_device() {
    const float priorities[2] = {1.0f, 1.0f};
    auto queue_info = vk_struct<VkDeviceQueueCreateInfo>(VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO);
    queue_info.queueFamilyIndex = queue_family_;
    queue_info.queueCount = queue_count_;
    queue_info.pQueuePriorities = priorities;
    auto device_info = vk_struct<VkDeviceCreateInfo>(VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO);
    device_info.queueCreateInfoCount = 1;
    device_info.pQueueCreateInfos = &queue_info;
    VkPhysicalDeviceProperties properties{};
    vkGetPhysicalDeviceProperties(physical_device_, &properties);
    auto v12 = vk_struct<VkPhysicalDeviceVulkan12Features>(VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES);
    if (instance_api_version_ >= VK_API_VERSION_1_2 && properties.apiVersion >= VK_API_VERSION_1_2) {
      auto features = vk_struct<VkPhysicalDeviceFeatures2>(VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2);
      features.pNext = &v12;
      vkGetPhysicalDeviceFeatures2(physical_device_, &features);
      const VkBool32 address = v12.bufferDeviceAddress, timeline = v12.timelineSemaphore;
      v12 = vk_struct<VkPhysicalDeviceVulkan12Features>(VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES);
      v12.bufferDeviceAddress = address;
      v12.timelineSemaphore = timeline;
      device_info.pNext = &v12;
    }
    foveart::gpu_engine::RayTracingDeviceSupport ray_tracing(physical_device_);
    std::vector<const char*> extensions;
    ray_tracing_ = ray_tracing.enable(&device_info, &extensions);
    trace_rays_indirect_ = ray_tracing_ && ray_tracing.trace_rays_indirect();
    auto device_create = xr_struct<XrVulkanDeviceCreateInfoKHR>(XR_TYPE_VULKAN_DEVICE_CREATE_INFO_KHR);
    device_create.systemId = system_;
    device_create.pfnGetInstanceProcAddr = &vkGetInstanceProcAddr;
    device_create.vulkanPhysicalDevice = physical_device_;
    device_create.vulkanCreateInfo = &device_info;
    VkResult vr = VK_SUCCESS;
    check(proc<PFN_xrCreateVulkanDeviceKHR>(instance_, "xrCreateVulkanDeviceKHR")(instance_, &device_create,
                                                                                  &device_, &vr),
          "xrCreateVulkanDeviceKHR");
    check(vr, "vkCreateDevice");
  }

  VulkanDevice vulkan_device() const {
    return VulkanDevice{physical_device_, device_, queue_family_, queue_, ray_tracing_, trace_rays_indirect_};
  }

  void create_session() {
    auto binding = xr_struct<XrGraphicsBindingVulkan2KHR>(XR_TYPE_GRAPHICS_BINDING_VULKAN2_KHR);
    binding.instance = vk_instance_;
    binding.physicalDevice = physical_device_;
    binding.device = device_;
    binding.queueFamilyIndex = queue_family_;
    binding.queueIndex = 0;
    auto info = xr_struct<XrSessionCreateInfo>(XR_TYPE_SESSION_CREATE_INFO);
    info.next = &binding;
    info.systemId = system_;
    check(xrCreateSession(instance_, &info, &session_), "xrCreateSession");
    auto space_info = xr_struct<XrReferenceSpaceCreateInfo>(XR_TYPE_REFERENCE_SPACE_CREATE_INFO);
    space_info.referenceSpaceType = XR_REFERENCE_SPACE_TYPE_LOCAL;
    // poseInReferenceSpace is the app space's origin in LOCAL: the inverse of
    // scene_from_local, so a pose located in space_ is in scene coordinates.
    space_info.poseInReferenceSpace = inverse(options_.scene_from_local);
    check(xrCreateReferenceSpace(session_, &space_info, &space_), "xrCreateReferenceSpace");
  }

  // The app's own eye gaze action, as an eye-tracked app would have it.
  void create_app_actions() {
    auto set_info = xr_struct<XrActionSetCreateInfo>(XR_TYPE_ACTION_SET_CREATE_INFO);
    std::strncpy(set_info.actionSetName, "hello_gaze", XR_MAX_ACTION_SET_NAME_SIZE - 1);
    std::strncpy(set_info.localizedActionSetName, "hello gaze", XR_MAX_LOCALIZED_ACTION_SET_NAME_SIZE - 1);
    check(xrCreateActionSet(instance_, &set_info, &app_set_), "xrCreateActionSet");
    auto action_info = xr_struct<XrActionCreateInfo>(XR_TYPE_ACTION_CREATE_INFO);
    action_info.actionType = XR_ACTION_TYPE_POSE_INPUT;
    std::strncpy(action_info.actionName, "gaze", XR_MAX_ACTION_NAME_SIZE - 1);
    std::strncpy(action_info.localizedActionName, "gaze", XR_MAX_LOCALIZED_ACTION_NAME_SIZE - 1);
    check(xrCreateAction(app_set_, &action_info, &app_action_), "xrCreateAction");
    XrPath profile = XR_NULL_PATH, pose = XR_NULL_PATH;
    check(xrStringToPath(instance_, "/interaction_profiles/ext/eye_gaze_interaction", &profile), "xrStringToPath");
    check(xrStringToPath(instance_, "/user/eyes_ext/input/gaze_ext/pose", &pose), "xrStringToPath");
    const XrActionSuggestedBinding binding{app_action_, pose};
    auto suggested = xr_struct<XrInteractionProfileSuggestedBinding>(XR_TYPE_INTERACTION_PROFILE_SUGGESTED_BINDING);
    suggested.interactionProfile = profile;
    suggested.countSuggestedBindings = 1;
    suggested.suggestedBindings = &binding;
    check(xrSuggestInteractionProfileBindings(instance_, &suggested), "xrSuggestInteractionProfileBindings");
    auto attach = xr_struct<XrSessionActionSetsAttachInfo>(XR_TYPE_SESSION_ACTION_SETS_ATTACH_INFO);
    attach.countActionSets = 1;
    attach.actionSets = &app_set_;
    check(xrAttachSessionActionSets(session_, &attach), "xrAttachSessionActionSets");
    auto space_info = xr_struct<XrActionSpaceCreateInfo>(XR_TYPE_ACTION_SPACE_CREATE_INFO);
    space_info.action = app_action_;
    space_info.poseInActionSpace.orientation.w = 1.0f;
    check(xrCreateActionSpace(session_, &space_info, &app_gaze_space_), "xrCreateActionSpace");
  }

  void locate_app_gaze(XrTime time, AppResult* result) {
    const XrActiveActionSet active{app_set_, XR_NULL_PATH};
    auto sync = xr_struct<XrActionsSyncInfo>(XR_TYPE_ACTIONS_SYNC_INFO);
    sync.countActiveActionSets = 1;
    sync.activeActionSets = &active;
    check(xrSyncActions(session_, &sync), "xrSyncActions");
    auto location = xr_struct<XrSpaceLocation>(XR_TYPE_SPACE_LOCATION);
    check(xrLocateSpace(app_gaze_space_, space_, time, &location), "xrLocateSpace");
    if (location.locationFlags & XR_SPACE_LOCATION_ORIENTATION_TRACKED_BIT) ++result->app_gaze_located_frames;
  }

  void create_swapchains() {
    uint32_t count = 0;
    check(xrEnumerateViewConfigurationViews(instance_, system_, XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO, 0, &count,
                                            nullptr),
          "xrEnumerateViewConfigurationViews");
    std::vector<XrViewConfigurationView> views(count, xr_struct<XrViewConfigurationView>(XR_TYPE_VIEW_CONFIGURATION_VIEW));
    check(xrEnumerateViewConfigurationViews(instance_, system_, XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO, count,
                                            &count, views.data()),
          "xrEnumerateViewConfigurationViews");
    if (count != 2) throw std::runtime_error("expected a stereo view configuration");
    for (uint32_t e = 0; e < 2; ++e) {
      auto info = xr_struct<XrSwapchainCreateInfo>(XR_TYPE_SWAPCHAIN_CREATE_INFO);
      info.usageFlags = XR_SWAPCHAIN_USAGE_COLOR_ATTACHMENT_BIT | XR_SWAPCHAIN_USAGE_TRANSFER_DST_BIT;
      info.format = VK_FORMAT_R8G8B8A8_SRGB;
      info.sampleCount = 1;
      info.width = options_.eye_width_px != 0 ? options_.eye_width_px : views[e].recommendedImageRectWidth;
      info.height = options_.eye_height_px != 0 ? options_.eye_height_px : views[e].recommendedImageRectHeight;
      if (info.width > views[e].maxImageRectWidth || info.height > views[e].maxImageRectHeight) {
        throw std::runtime_error("eye size " + std::to_string(info.width) + "x" + std::to_string(info.height) +
                                 " exceeds the runtime's maximum");
      }
      info.faceCount = 1;
      info.arraySize = 1;
      info.mipCount = 1;
      check(xrCreateSwapchain(session_, &info, &eyes_[e].handle), "xrCreateSwapchain");
      eyes_[e].width = static_cast<int32_t>(info.width);
      eyes_[e].height = static_cast<int32_t>(info.height);
      uint32_t n = 0;
      check(xrEnumerateSwapchainImages(eyes_[e].handle, 0, &n, nullptr), "xrEnumerateSwapchainImages");
      std::vector<XrSwapchainImageVulkan2KHR> images(n, xr_struct<XrSwapchainImageVulkan2KHR>(XR_TYPE_SWAPCHAIN_IMAGE_VULKAN2_KHR));
      check(xrEnumerateSwapchainImages(eyes_[e].handle, n, &n,
                                       reinterpret_cast<XrSwapchainImageBaseHeader*>(images.data())),
            "xrEnumerateSwapchainImages");
      for (const auto& image : images) eyes_[e].images.push_back(image.image);
    }
  }

  // The engine's device trace on the session's device and queue, if it has one.
  void create_device_trace() {
    if (!options_.make_device_trace) return;
    device_trace_made_ = true;  // released at shutdown even if making it threw half-way
    device_trace_ = options_.make_device_trace(vulkan_device());
    if (!options_.app_recorded_trace) return;
    if (device_trace_.trace_rays_device == nullptr)
      throw std::runtime_error("the app-recorded trace needs a device trace");
    app_trace_ = std::make_unique<AppRecordedTrace>(device_, queue_family_, trace_queue_);
  }

  // --mode full: the app's own renderer of every view, on the session's device.
  void create_view_renderer() {
    if (!options_.make_view_renderer) return;
    view_renderer_ = options_.make_view_renderer(vulkan_device());
    if (view_renderer_ == nullptr) throw std::runtime_error("the full render could not be set up");
  }

  void create_renderer() {
    auto info = xr_struct<XrFoveatedRendererCreateInfoFOVEART>(XR_TYPE_FOVEATED_RENDERER_CREATE_INFO_FOVEART);
    auto device_trace = xr_struct<XrFoveatedDeviceTraceInfoFOVEART>(XR_TYPE_FOVEATED_DEVICE_TRACE_INFO_FOVEART);
    auto app_trace = xr_struct<XrFoveatedAppTraceInfoFOVEART>(XR_TYPE_FOVEATED_APP_TRACE_INFO_FOVEART);
    if (app_trace_ != nullptr) {
      info.next = &app_trace;  // one queue family: the layer's buffers stay exclusive to it
    } else if (device_trace_.trace_rays_device != nullptr) {
      device_trace.traceRaysDevice = device_trace_.trace_rays_device;
      device_trace.userData = device_trace_.user_data;
      info.next = &device_trace;
    }
    info.traceRays = options_.trace_rays;
    info.userData = options_.user_data;
    info.interpolation = options_.interpolation;
    info.k = options_.k;
    info.densityScale = options_.density_scale;
    info.raysPerPoint = options_.rays_per_point;
    info.temporal = options_.temporal;
    info.gazeSource = options_.gaze_source;
    info.gazeProviderSpec = options_.gaze_provider.empty() ? nullptr : options_.gaze_provider.c_str();
    check(create_renderer_(session_, &info, &renderer_), "xrCreateFoveatedRendererFOVEART");
  }

  // The placeholder: a grey clear. It is what the runtime shows if the layer
  // falls back for a view.
  void clear_placeholder(uint32_t e, uint32_t index) {
    const VkCommandBuffer command_buffer = placeholder_.buffers[0];
    VkFence& fence = placeholder_.fences[0];
    check(vkResetCommandBuffer(command_buffer, 0), "vkResetCommandBuffer");
    auto begin = vk_struct<VkCommandBufferBeginInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO);
    begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    check(vkBeginCommandBuffer(command_buffer, &begin), "vkBeginCommandBuffer");
    auto barrier = vk_struct<VkImageMemoryBarrier>(VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER);
    barrier.dstAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    barrier.oldLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    barrier.newLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
    barrier.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    barrier.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    barrier.image = eyes_[e].images[index];
    barrier.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    vkCmdPipelineBarrier(command_buffer, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 0,
                         nullptr, 0, nullptr, 1, &barrier);
    VkClearColorValue grey{};
    grey.float32[0] = grey.float32[1] = grey.float32[2] = 0.2f;
    grey.float32[3] = 1.0f;
    vkCmdClearColorImage(command_buffer, barrier.image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &grey, 1,
                         &barrier.subresourceRange);
    barrier.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    barrier.dstAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
    barrier.oldLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
    barrier.newLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    vkCmdPipelineBarrier(command_buffer, VK_PIPELINE_STAGE_TRANSFER_BIT,
                         VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT, 0, 0, nullptr, 0, nullptr, 1, &barrier);
    check(vkEndCommandBuffer(command_buffer), "vkEndCommandBuffer");
    check(vkResetFences(device_, 1, &fence), "vkResetFences");
    auto submit = vk_struct<VkSubmitInfo>(VK_STRUCTURE_TYPE_SUBMIT_INFO);
    submit.commandBufferCount = 1;
    submit.pCommandBuffers = &command_buffer;
    check(vkQueueSubmit(queue_, 1, &submit, fence), "vkQueueSubmit");
    check(vkWaitForFences(device_, 1, &fence, VK_TRUE, UINT64_MAX), "vkWaitForFences");
  }

  bool poll_events() {
    for (;;) {
      auto event = xr_struct<XrEventDataBuffer>(XR_TYPE_EVENT_DATA_BUFFER);
      const XrResult r = xrPollEvent(instance_, &event);
      check(r, "xrPollEvent");
      if (r == XR_EVENT_UNAVAILABLE) return true;
      if (event.type == XR_TYPE_EVENT_DATA_INSTANCE_LOSS_PENDING) return false;
      if (event.type != XR_TYPE_EVENT_DATA_SESSION_STATE_CHANGED) continue;
      const auto& changed = *reinterpret_cast<const XrEventDataSessionStateChanged*>(&event);
      state_ = changed.state;
      if (state_ == XR_SESSION_STATE_READY) {
        auto begin = xr_struct<XrSessionBeginInfo>(XR_TYPE_SESSION_BEGIN_INFO);
        begin.primaryViewConfigurationType = XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO;
        check(xrBeginSession(session_, &begin), "xrBeginSession");
        running_ = true;
      } else if (state_ == XR_SESSION_STATE_STOPPING) {
        check(xrEndSession(session_), "xrEndSession");
        running_ = false;
      } else if (state_ == XR_SESSION_STATE_EXITING || state_ == XR_SESSION_STATE_LOSS_PENDING) {
        return false;
      }
    }
  }

  void loop(AppResult* result) {
    while (poll_events()) {
      if (options_.max_frames != 0 && frames_ >= options_.max_frames) break;
      if (!running_) continue;
      frame(result);
    }
  }

  // One frame: wait, begin, draw both eyes, end; then its times and the layer's stats.
  void frame(AppResult* result) {
    auto wait_info = xr_struct<XrFrameWaitInfo>(XR_TYPE_FRAME_WAIT_INFO);
    auto frame_state = xr_struct<XrFrameState>(XR_TYPE_FRAME_STATE);
    check(xrWaitFrame(session_, &wait_info, &frame_state), "xrWaitFrame");
    auto begin_info = xr_struct<XrFrameBeginInfo>(XR_TYPE_FRAME_BEGIN_INFO);
    const auto frame_t0 = std::chrono::steady_clock::now();
    check(xrBeginFrame(session_, &begin_info), "xrBeginFrame");
    if (options_.app_actions) locate_app_gaze(frame_state.predictedDisplayTime, result);
    const std::array<XrView, 2> views = locate_views(frame_state.predictedDisplayTime);
    if (app_trace_ != nullptr && frame_state.shouldRender) trace_in_app(frame_state.predictedDisplayTime, views, result);
    std::array<XrCompositionLayerProjectionView, 2> projection_views{};
    for (uint32_t e = 0; e < 2; ++e) projection_views[e] = draw_eye(e, views[e]);
    const float end_frame_ms = end_frame(frame_state, projection_views);
    const auto frame_ms = static_cast<float>(
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - frame_t0).count());
    if (view_renderer_ != nullptr) {
      result->frame_ms.push_back(frame_ms);
      result->end_frame_host_ms.push_back(end_frame_ms);
    }
    const auto frame_index = static_cast<float>(frames_);
    for (uint32_t e = 0; e < 2; ++e) {
      result->views[e] = {projection_views[e].pose, projection_views[e].fov, eyes_[e].width, eyes_[e].height};
    }
    ++frames_;
    record_stats(frame_state.predictedDisplayTime, {frame_ms, end_frame_ms}, frame_index, result);
  }

  // The app-recorded trace: the frame's rays acquired, traced in the app's own
  // command buffer and submitted, the batch released (release_fault aside).
  void trace_in_app(XrTime display_time, const std::array<XrView, 2>& views, AppResult* result) {
    const XrExtent2Di sizes[2] = {{eyes_[0].width, eyes_[0].height}, {eyes_[1].width, eyes_[1].height}};
    auto acquire = xr_struct<XrFoveatedRayBatchAcquireInfoFOVEART>(XR_TYPE_FOVEATED_RAY_BATCH_ACQUIRE_INFO_FOVEART);
    acquire.displayTime = display_time;
    acquire.space = space_;
    acquire.viewCount = 2;
    std::array<XrView, 2> acquired = views;
    if (options_.release_fault == "moved")
      for (XrView& v : acquired) v.pose.position.x += 0.01f;  // the layer's views differ at xrEndFrame
    if (options_.release_fault == "nan")
      for (XrView& v : acquired) v.pose.position.y = std::numeric_limits<float>::quiet_NaN();  // no rays
    acquire.views = acquired.data();
    acquire.imageSizes = sizes;
    std::array<XrFoveatedDeviceRayBatchFOVEART, 2> per_view{};
    auto batch = xr_struct<XrFoveatedRayBatchFOVEART>(XR_TYPE_FOVEATED_RAY_BATCH_FOVEART);
    batch.viewCapacityInput = 2;
    batch.views = per_view.data();
    check(acquire_batch_(renderer_, &acquire, &batch), "xrAcquireFoveatedRayBatchFOVEART");
    app_trace_->trace(batch, device_trace_.trace_rays_device, device_trace_.user_data);
    const std::string& fault = options_.release_fault;
    if (fault == "never") return;
    const uint64_t id = fault == "unknown" ? batch.batchId + 1000 : batch.batchId;
    for (int i = 0; i < (fault == "twice" ? 2 : 1); ++i) {
      const XrResult r = release_batch_(renderer_, id);
      if (XR_FAILED(r)) ++result->release_errors, result->last_release_error = r;
    }
  }

  std::array<XrView, 2> locate_views(XrTime display_time) {
    std::array<XrView, 2> views{xr_struct<XrView>(XR_TYPE_VIEW), xr_struct<XrView>(XR_TYPE_VIEW)};
    auto locate = xr_struct<XrViewLocateInfo>(XR_TYPE_VIEW_LOCATE_INFO);
    locate.viewConfigurationType = XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO;
    locate.displayTime = display_time;
    locate.space = space_;
    auto view_state = xr_struct<XrViewState>(XR_TYPE_VIEW_STATE);
    uint32_t view_count = 0;
    check(xrLocateViews(session_, &locate, &view_state, 2, &view_count, views.data()), "xrLocateViews");
    return views;
  }

  // Eye e's swapchain image, drawn by the full renderer or left as the placeholder; its projection view.
  XrCompositionLayerProjectionView draw_eye(uint32_t e, const XrView& view) {
    uint32_t index = 0;
    auto acquire = xr_struct<XrSwapchainImageAcquireInfo>(XR_TYPE_SWAPCHAIN_IMAGE_ACQUIRE_INFO);
    check(xrAcquireSwapchainImage(eyes_[e].handle, &acquire, &index), "xrAcquireSwapchainImage");
    auto wait = xr_struct<XrSwapchainImageWaitInfo>(XR_TYPE_SWAPCHAIN_IMAGE_WAIT_INFO);
    wait.timeout = XR_INFINITE_DURATION;
    check(xrWaitSwapchainImage(eyes_[e].handle, &wait), "xrWaitSwapchainImage");
    if (view_renderer_ != nullptr) {
      view_renderer_->render(e, view.pose, view.fov, eyes_[e].images[index], static_cast<uint32_t>(eyes_[e].width),
                             static_cast<uint32_t>(eyes_[e].height));
    } else {
      clear_placeholder(e, index);
    }
    auto release = xr_struct<XrSwapchainImageReleaseInfo>(XR_TYPE_SWAPCHAIN_IMAGE_RELEASE_INFO);
    check(xrReleaseSwapchainImage(eyes_[e].handle, &release), "xrReleaseSwapchainImage");
    auto projection_view = xr_struct<XrCompositionLayerProjectionView>(XR_TYPE_COMPOSITION_LAYER_PROJECTION_VIEW);
    projection_view.pose = view.pose;
    projection_view.fov = view.fov;
    projection_view.subImage.swapchain = eyes_[e].handle;
    projection_view.subImage.imageRect = {{0, 0}, {eyes_[e].width, eyes_[e].height}};
    return projection_view;
  }

  // Submits the projection layer, opted in to the layer unless the app renders it in full;
  // the host wall time of the xrEndFrame call in ms.
  float end_frame(const XrFrameState& frame_state,
                 const std::array<XrCompositionLayerProjectionView, 2>& projection_views) {
    // The opt-in: chained first into the projection layer.
    auto foveated = xr_struct<XrFoveatedRayTracingLayerFOVEART>(XR_TYPE_FOVEATED_RAY_TRACING_LAYER_FOVEART);
    foveated.renderer = renderer_;
    // The engine's exposure and curve for this frame, after the opt-in.
    auto display = xr_struct<XrFoveatedDisplayTransformFOVEART>(XR_TYPE_FOVEATED_DISPLAY_TRANSFORM_FOVEART);
    display.exposure = options_.exposure;
    display.toneMap = options_.tone_map;
    if (options_.exposure != 0.0f || options_.tone_map != XR_FOVEATED_TONE_MAP_USE_CONFIG_FOVEART)
      foveated.next = &display;
    auto layer = xr_struct<XrCompositionLayerProjection>(XR_TYPE_COMPOSITION_LAYER_PROJECTION);
    layer.next = view_renderer_ != nullptr ? nullptr : &foveated;  // a full render opts out
    layer.space = space_;
    layer.viewCount = 2;
    layer.views = projection_views.data();
    const XrCompositionLayerBaseHeader* layers[] = {reinterpret_cast<const XrCompositionLayerBaseHeader*>(&layer)};
    auto end = xr_struct<XrFrameEndInfo>(XR_TYPE_FRAME_END_INFO);
    end.displayTime = frame_state.predictedDisplayTime;
    end.environmentBlendMode = XR_ENVIRONMENT_BLEND_MODE_OPAQUE;
    end.layerCount = frame_state.shouldRender ? 1 : 0;
    end.layers = layers;
    const auto t0 = std::chrono::steady_clock::now();
    const XrResult r = xrEndFrame(session_, &end);
    const auto ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    check(r, "xrEndFrame");
    return static_cast<float>(ms);
  }

  struct FrameTimes {
    float frame_ms;      // xrBeginFrame's call to xrEndFrame's return
    float end_frame_ms;  // the xrEndFrame call
  };

  // The layer's stats after a frame; a frame it traced adds its per-frame entries to *result.
  void record_stats(XrTime display_time, FrameTimes times, float frame_index, AppResult* result) {
    auto reconstruction =
        xr_struct<XrFoveatedRendererReconstructionStatsFOVEART>(XR_TYPE_FOVEATED_RENDERER_RECONSTRUCTION_STATS_FOVEART);
    auto stats = xr_struct<XrFoveatedRendererStatsFOVEART>(XR_TYPE_FOVEATED_RENDERER_STATS_FOVEART);
    stats.next = &reconstruction;
    auto density = xr_struct<XrFoveatedRendererDensityStatsFOVEART>(XR_TYPE_FOVEATED_RENDERER_DENSITY_STATS_FOVEART);
    reconstruction.next = &density;
    auto app_trace = xr_struct<XrFoveatedAppTraceStatsFOVEART>(XR_TYPE_FOVEATED_APP_TRACE_STATS_FOVEART);
    if (app_trace_ != nullptr) density.next = &app_trace;
    check(get_stats_(renderer_, &stats), "xrGetFoveatedRendererStatsFOVEART");
    if (stats.framesTraced <= traced_) return;
    traced_ = stats.framesTraced;
    if (app_trace_ != nullptr) result->acquire_to_end_frame_ms.push_back(app_trace.acquireToEndFrameMs);
    result->frame_ms.push_back(times.frame_ms);
    result->end_frame_host_ms.push_back(times.end_frame_ms);
    result->gaze_px.push_back(
        {frame_index, stats.gazePixel[0].x, stats.gazePixel[0].y, stats.gazePixel[1].x, stats.gazePixel[1].y});
    result->temporal_reset.push_back(
        {reconstruction.temporalResetLastFrame[0] == XR_TRUE, reconstruction.temporalResetLastFrame[1] == XR_TRUE});
    result->gaze_saccade.push_back(reconstruction.gazeSaccadeLastFrame == XR_TRUE);
    result->gaze_blink.push_back(reconstruction.gazeBlinkLastFrame == XR_TRUE);
    if (first_traced_display_time_ == 0) first_traced_display_time_ = display_time;
    result->display_time_s.push_back(static_cast<double>(display_time - first_traced_display_time_) * 1e-9);
    if (stats.gazeSource != XR_FOVEATED_GAZE_SOURCE_NONE_FOVEART) result->gaze_age_ms.push_back(stats.gazeAgeMs);
    for (int e = 0; e < 2; ++e) {
      result->overhead_ms[e].push_back(stats.selectMs[e] + stats.reconstructMs[e] + stats.temporalMs[e] + stats.uploadMs[e]);
      result->trace_ms[e].push_back(stats.traceMs[e]);
      result->density_ms[e].push_back(density.levelsMs[e] + density.testMs[e] + density.observeMs[e] +
                                      density.fillMs[e]);
    }
    record_gpu_times(stats, reconstruction, density, result);
  }

  // The GPU path's times per eye where the stats have them (a finished frame, up
  // to two older than this one), once per finished frame: the trace slot and the
  // eye's stages in all.
  static void record_gpu_times(const XrFoveatedRendererStatsFOVEART& stats,
                               const XrFoveatedRendererReconstructionStatsFOVEART& reconstruction,
                               const XrFoveatedRendererDensityStatsFOVEART& density, AppResult* result) {
    if (reconstruction.path != XR_FOVEATED_RECONSTRUCTION_PATH_GPU_FOVEART) return;
    float eye_ms[2];
    for (int e = 0; e < 2; ++e)
      eye_ms[e] = stats.traceMs[e] + reconstruction.gpuScatterMs[e] + reconstruction.gpuGatherMs[e] +
                  reconstruction.gpuTemporalMs[e] + reconstruction.gpuEncodeMs[e];
    if (!(eye_ms[0] > 0.0f && eye_ms[1] > 0.0f)) return;  // no frame finished yet
    if (!result->gpu_eye_ms[0].empty() && result->gpu_eye_ms[0].back() == eye_ms[0] &&
        result->gpu_eye_ms[1].back() == eye_ms[1])
      return;  // the same finished frame read again
    for (int e = 0; e < 2; ++e) {
      result->gpu_trace_ms[e].push_back(stats.traceMs[e]);
      result->gpu_eye_ms[e].push_back(eye_ms[e]);
      result->gpu_density_fill_ms[e].push_back(density.gpuFillMs[e]);
      result->gpu_density_contrast_ms[e].push_back(density.gpuContrastMs[e]);
    }
    result->gpu_frame_ms.push_back(eye_ms[0] + eye_ms[1]);
  }

  void shutdown() noexcept {
    // The app's traces use the renderer's semaphore: finished before the renderer goes (the header's "Lifetime").
    if (app_trace_ != nullptr) vkDeviceWaitIdle(device_);
    if (renderer_ != XR_NULL_HANDLE && destroy_renderer_ != nullptr) destroy_renderer_(renderer_);
    renderer_ = XR_NULL_HANDLE;
    for (auto& eye : eyes_) {
      if (eye.handle != XR_NULL_HANDLE) xrDestroySwapchain(eye.handle);
      eye.handle = XR_NULL_HANDLE;
    }
    if (app_gaze_space_ != XR_NULL_HANDLE) xrDestroySpace(app_gaze_space_);
    app_gaze_space_ = XR_NULL_HANDLE;
    if (space_ != XR_NULL_HANDLE) xrDestroySpace(space_);
    space_ = XR_NULL_HANDLE;
    if (session_ != XR_NULL_HANDLE) xrDestroySession(session_);
    session_ = XR_NULL_HANDLE;
    if (device_ != VK_NULL_HANDLE) {
      vkDeviceWaitIdle(device_);
      // The engine's objects on the device go before it (nothing of theirs is in flight now).
      view_renderer_.reset();
      app_trace_.reset();  // its submissions finished (the device is idle)
      if (device_trace_made_ && options_.release_device_trace) options_.release_device_trace();
      device_trace_made_ = false;
      placeholder_.destroy(device_);
      vkDestroyDevice(device_, nullptr);
      device_ = VK_NULL_HANDLE;
    }
    if (vk_instance_ != VK_NULL_HANDLE) vkDestroyInstance(vk_instance_, nullptr);
    vk_instance_ = VK_NULL_HANDLE;
    if (instance_ != XR_NULL_HANDLE) xrDestroyInstance(instance_);
    instance_ = XR_NULL_HANDLE;
  }

  AppOptions options_;
  XrInstance instance_ = XR_NULL_HANDLE;
  XrSystemId system_ = XR_NULL_SYSTEM_ID;
  XrSession session_ = XR_NULL_HANDLE;
  XrSpace space_ = XR_NULL_HANDLE;
  XrActionSet app_set_ = XR_NULL_HANDLE;
  XrAction app_action_ = XR_NULL_HANDLE;
  XrSpace app_gaze_space_ = XR_NULL_HANDLE;
  XrSessionState state_ = XR_SESSION_STATE_UNKNOWN;
  bool running_ = false;
  uint64_t frames_ = 0;
  uint64_t traced_ = 0;
  XrTime first_traced_display_time_ = 0;
  EyeSwapchain eyes_[2];
  VkInstance vk_instance_ = VK_NULL_HANDLE;
  VkPhysicalDevice physical_device_ = VK_NULL_HANDLE;
  VkDevice device_ = VK_NULL_HANDLE;
  uint32_t queue_family_ = 0;
  VkQueue queue_ = VK_NULL_HANDLE;
  VkQueue trace_queue_ = VK_NULL_HANDLE;  // the app-recorded trace's: a second queue, else queue_
  uint32_t queue_count_ = 1;              // of queue_family_: 2 where the app-recorded trace has a second queue
  uint32_t instance_api_version_ = VK_API_VERSION_1_1;
  bool ray_tracing_ = false;          // the ray-tracing pipeline's extensions enabled (create_device)
  bool trace_rays_indirect_ = false;
  CommandPool placeholder_;  // the placeholder clear's command buffer and fence
  PFN_xrCreateFoveatedRendererFOVEART create_renderer_ = nullptr;
  PFN_xrDestroyFoveatedRendererFOVEART destroy_renderer_ = nullptr;
  PFN_xrGetFoveatedRendererStatsFOVEART get_stats_ = nullptr;
  PFN_xrAcquireFoveatedRayBatchFOVEART acquire_batch_ = nullptr;
  PFN_xrReleaseFoveatedRayBatchFOVEART release_batch_ = nullptr;
  XrFoveatedRendererFOVEART renderer_ = XR_NULL_HANDLE;
  DeviceTrace device_trace_;
  std::unique_ptr<ViewRenderer> view_renderer_;
  std::unique_ptr<AppRecordedTrace> app_trace_;  // app_recorded_trace
  bool device_trace_made_ = false;
};

}  // namespace

AppResult run_app(const AppOptions& options) {
  try {
    App app(options);
    return app.run();
  } catch (const std::exception& e) {
    AppResult result;
    result.error = e.what();
    return result;
  }
}

}  // namespace foveart::hello
