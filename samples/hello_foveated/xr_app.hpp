// A minimal OpenXR + Vulkan2 client: instance with the FoveaRT layer and
// extension, session on a device the runtime picks, one placeholder swapchain
// per eye (cleared, never shaded: the layer replaces those views), the frame
// loop, and the foveated renderer around it.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#define XR_USE_GRAPHICS_API_VULKAN
#include <vulkan/vulkan.h>
#include <openxr/openxr.h>
#include <openxr/openxr_platform.h>

#include "layer/XR_FOVEART_foveated_ray_tracing.h"

namespace foveart::hello {

// The session's Vulkan device, for an engine that traces on it.
struct VulkanDevice {
  VkPhysicalDevice physical_device = VK_NULL_HANDLE;
  VkDevice device = VK_NULL_HANDLE;
  uint32_t queue_family_index = 0;
  VkQueue queue = VK_NULL_HANDLE;  // the session's queue: the layer submits there too
  bool ray_tracing = false;          // created with RayTracingDeviceSupport::enable (gpu_engine::GpuContext)
  bool trace_rays_indirect = false;  // ... and its rayTracingPipelineTraceRaysIndirect
};

// The app's own image of a view (--mode full): drawn into the acquired
// swapchain image instead of the grey placeholder, and the frame does not opt
// into the layer's foveated ray tracing.
class ViewRenderer {
 public:
  virtual ~ViewRenderer() = default;
  // image: the acquired swapchain image of eye `eye` (R8G8B8A8_SRGB, width_px x
  // height_px, content undefined); left in COLOR_ATTACHMENT_OPTIMAL, its writes
  // finished. pose/fov: the view as submitted (the app's space is the scene's).
  // Throws std::exception on failure (run_app's error).
  virtual void render(uint32_t eye, const XrPosef& pose, const XrFovf& fov, VkImage image, uint32_t width_px,
                      uint32_t height_px) = 0;
};

// A device trace to chain into the renderer (XrFoveatedDeviceTraceInfoFOVEART).
struct DeviceTrace {
  PFN_xrFoveatedTraceRaysDeviceFOVEART trace_rays_device = nullptr;  // null: no device trace
  void* user_data = nullptr;
};

struct AppOptions {
  FoveartTraceRaysFn trace_rays = nullptr;  // may be null with a device trace
  void* user_data = nullptr;
  // Optional, for an engine on the GPU: called once the session's device
  // exists, before the renderer is created, on the app's thread; returns the
  // device trace to chain (a null function: none). Throwing (std::exception)
  // fails the run with its message.
  std::function<DeviceTrace(const VulkanDevice&)> make_device_trace;
  // Called once make_device_trace was called (even if it threw), at shutdown: after the renderer is
  // destroyed and the device is idle, before the device is destroyed; release
  // what make_device_trace made on it. Must not throw.
  std::function<void()> release_device_trace;
  // Optional (--mode full): called after make_device_trace; the app then draws
  // every view with it and never chains XrFoveatedRayTracingLayerFOVEART (the
  // layer passes the views through). Destroyed before release_device_trace.
  std::function<std::unique_ptr<ViewRenderer>(const VulkanDevice&)> make_view_renderer;
  // The renderer's settings; each default leaves the setting to the layer's
  // config (the extension header's "Defaults").
  XrFoveatedInterpolationFOVEART interpolation = XR_FOVEATED_INTERPOLATION_USE_CONFIG_FOVEART;
  uint32_t k = 0;
  float density_scale = 0.0f;
  uint32_t rays_per_point = 0;
  XrFoveatedTemporalFOVEART temporal = XR_FOVEATED_TEMPORAL_USE_CONFIG_FOVEART;
  XrFoveatedGazeSourceFOVEART gaze_source = XR_FOVEATED_GAZE_SOURCE_USE_CONFIG_FOVEART;
  std::string gaze_provider;
  // Chained into every frame as XrFoveatedDisplayTransformFOVEART unless both say
  // "use the config": the exposure (linear, > 0; 0 = config) and the curve.
  float exposure = 0.0f;
  XrFoveatedToneMapFOVEART tone_map = XR_FOVEATED_TONE_MAP_USE_CONFIG_FOVEART;
  bool enable_layer = true;   // false when the layer is enabled implicitly / by XR_ENABLE_API_LAYERS
  uint64_t max_frames = 0;    // 0: until the runtime ends the session
  uint32_t eye_width_px = 0;  // 0: the runtime's recommended size
  uint32_t eye_height_px = 0;
  // Test aid: the app enables XR_EXT_eye_gaze_interaction itself and uses its
  // own gaze action (suggest, attach, sync, locate) next to the layer's.
  bool app_actions = false;
  // --trace-model app: the device trace that make_device_trace returns is
  // recorded by the app in its own command buffers, on a second queue where the
  // device has one, through xrAcquireFoveatedRayBatchFOVEART (the app-recorded
  // trace); the layer never calls it. Needs a device trace and Vulkan 1.2's timelineSemaphore.
  bool app_recorded_trace = false;
  // Test aid with app_recorded_trace: "never" (the batch is never released),
  // "twice" (released twice), "unknown" (an unknown id released instead of it),
  // "moved" (acquired for views 1 cm off those submitted).
  std::string release_fault;
  // Where the headset's LOCAL origin sits in the scene (the scene's camera):
  // the app's space is LOCAL offset by this pose, so rays come out in scene space.
  XrPosef scene_from_local{{0.0f, 0.0f, 0.0f, 1.0f}, {0.0f, 0.0f, 0.0f}};
};

struct AppResult {
  bool ok = false;
  std::string error;
  uint64_t frames = 0;
  XrFoveatedRendererStatsFOVEART stats{};
  XrFoveatedRendererReconstructionStatsFOVEART reconstruction{};  // chained into stats at the end
  XrFoveatedRendererDensityStatsFOVEART density{};                // ... as well
  // The last frame's submitted projection views (pose in the app's space, which
  // is the scene's; FOV; image size): what the layer traced them from.
  struct SubmittedView {
    XrPosef pose{{0.0f, 0.0f, 0.0f, 1.0f}, {0.0f, 0.0f, 0.0f}};
    XrFovf fov{};
    int32_t width_px = 0, height_px = 0;
  };
  SubmittedView views[2];
  // Per traced frame: gaze age at composition, and the layer's own time per eye
  // excluding the callback (select + reconstruct + temporal + upload).
  std::vector<float> gaze_age_ms;
  std::vector<float> overhead_ms[2];
  std::vector<float> trace_ms[2];
  // Per traced frame: content density's host ms (XrFoveatedRendererDensityStatsFOVEART's
  // levels + test + observe + fill; 0 on a device trace or while off).
  std::vector<float> density_ms[2];
  // Per rendered frame (foveated: the frames the layer traced; full: every
  // frame): xrBeginFrame's call to xrEndFrame's return, as the app sees it.
  std::vector<float> frame_ms;
  // Per rendered frame as frame_ms: the host wall time of the xrEndFrame call alone
  // (the layer's work on the app's thread: its submissions and waits).
  std::vector<float> end_frame_host_ms;
  // Per finished frame on the GPU path whose times the stats held (the newest
  // finished frame, up to two older than the last; one read again is kept once),
  // per eye: the device trace's slot of traceMs, and the eye's GPU time in all
  // (+ scatter, gather, temporal, encode with the copy into the image); and both
  // eyes' sum.
  std::vector<float> gpu_trace_ms[2];
  std::vector<float> gpu_eye_ms[2];
  std::vector<float> gpu_frame_ms;
  // ... and, within gpu_trace_ms, content density's passes on the device: fill and contrast.
  std::vector<float> gpu_density_fill_ms[2];
  std::vector<float> gpu_density_contrast_ms[2];
  // Per traced frame: frame index, then the layer's gaze pixel of each eye (x, y).
  std::vector<std::array<float, 5>> gaze_px;
  uint64_t app_gaze_located_frames = 0;  // app_actions: frames its own gaze action located
  // Per traced frame, in the order of gaze_px (XrFoveatedRendererReconstructionStatsFOVEART,
  // chained every frame): whether each eye's temporal history restarted, and whether the gaze
  // provider flagged a saccade or a blink for that frame; and the frame's predicted display
  // time in seconds after the first traced frame's.
  std::vector<std::array<bool, 2>> temporal_reset;
  std::vector<bool> gaze_saccade;
  std::vector<bool> gaze_blink;
  std::vector<double> display_time_s;
  // app_recorded_trace: the layer's counts, and per traced frame how much older
  // the rays' gaze is than at xrEndFrame (acquire to xrEndFrame); the releases
  // the layer refused and the last error; whether the trace ran on a second queue.
  XrFoveatedAppTraceStatsFOVEART app_trace{};
  std::vector<float> acquire_to_end_frame_ms;
  uint64_t release_errors = 0;
  int32_t last_release_error = 0;
  bool second_queue = false;
};

AppResult run_app(const AppOptions& options);

}  // namespace foveart::hello
