// Stages 1-3 of a frame on the device, for an engine that registered a
// device trace (XrFoveatedDeviceTraceInfoFOVEART; docs/gpu.md "The device
// trace"): shaders/device_rays.comp selects the visible points and makes
// their rays from the gaze offset and the view (push constants), the engine
// records its trace of them into the frame's command buffer, and
// shaders/device_resolve.comp averages each point's rays into the slots the
// gather reads. No ray or colour crosses to the host: per frame the host
// reads back only the resolve's status (two words).
//
// Threads: as GpuEye (one thread at a time); each frame's submission has
// finished before the next record (the layer waits in xrEndFrame). Nothing
// here throws.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#ifndef XR_USE_GRAPHICS_API_VULKAN
#define XR_USE_GRAPHICS_API_VULKAN
#endif
#include <vulkan/vulkan.h>
#include <openxr/openxr.h>

#include "foveation/gaze_mapping.hpp"
#include "foveation/point_set.hpp"
#include "foveation/ray_samples.hpp"
#include "layer/XR_FOVEART_foveated_ray_tracing.h"
#include "vk_util.hpp"

namespace foveart::layer {

class GpuReconstructor;

// The engine's device trace, as registered.
struct DeviceTraceFn {
  PFN_xrFoveatedTraceRaysDeviceFOVEART trace = nullptr;
  void* user_data = nullptr;
};

// What one eye's device-traced frame needs.
struct DeviceTraceFrame {
  DeviceTraceFn engine;
  const foveation::PointSet* points = nullptr;  // the view tables' set
  FoveartEyeView view{};
  foveation::GazeMapping mapping;
  std::uint64_t frame_index = 0;
  std::uint64_t sample_seed = 0;
  std::uint32_t rays_per_point = 1;
  foveation::PixelFilter pixel_filter = foveation::PixelFilter::box;
};

// What the resolve found (read after the submission finished).
struct DeviceTraceStatus {
  std::uint64_t invalid_components = 0;  // NaN, infinite or negative colour components
  std::uint32_t visible_points = 0;
};

// The device trace's shaders, shared by the eyes of one device.
class GpuDeviceTracePipelines {
 public:
  static std::unique_ptr<GpuDeviceTracePipelines> create(VkDevice device, std::string* error);
  ~GpuDeviceTracePipelines();
  GpuDeviceTracePipelines(const GpuDeviceTracePipelines&) = delete;
  GpuDeviceTracePipelines& operator=(const GpuDeviceTracePipelines&) = delete;

 private:
  friend class GpuDeviceTrace;
  GpuDeviceTracePipelines() = default;
  VkDevice device_ = VK_NULL_HANDLE;
  VkDescriptorSetLayout rays_set_layout_ = VK_NULL_HANDLE, resolve_set_layout_ = VK_NULL_HANDLE;
  VkPipelineLayout rays_layout_ = VK_NULL_HANDLE, resolve_layout_ = VK_NULL_HANDLE;
  VkPipeline rays_ = VK_NULL_HANDLE, resolve_ = VK_NULL_HANDLE;
};

// One eye's rays, colours and counts on the device.
class GpuDeviceTrace {
 public:
  explicit GpuDeviceTrace(GpuReconstructor& owner);
  ~GpuDeviceTrace();
  GpuDeviceTrace(const GpuDeviceTrace&) = delete;
  GpuDeviceTrace& operator=(const GpuDeviceTrace&) = delete;

  // Records the frame's rays, the engine's trace and the resolve into `cb`,
  // writing every visible point's colour (a = 1) and depth into `colors` and
  // `point_depth` (cleared by the caller). false with *error when a buffer
  // cannot be made or the engine's call fails (engine_result() says which).
  [[nodiscard]] bool record(VkCommandBuffer cb, const DeviceTraceFrame& frame, VkBuffer colors, VkBuffer point_depth,
              std::string* error);
  // The engine's answer to the last record (XR_SUCCESS when it was not called).
  XrResult engine_result() const { return engine_result_; }
  // Bytes the host wrote for the last record: the point set, once per table set; else 0.
  std::uint64_t host_bytes_written() const { return uploaded_bytes_; }
  // After the submission finished: what the resolve found (the frame's one
  // read-back: FOVEART_DEVICE_STATUS_WORDS words).
  DeviceTraceStatus status() const;

 private:
  [[nodiscard]] bool ensure_buffers(const foveation::PointSet& points, std::uint32_t rays_per_point, std::string* error);
  void update_descriptors(VkBuffer colors, VkBuffer point_depth);
  // The steps of record: stages 1-2 (the rays), stage 3 (the engine's trace), the colours per point.
  void record_rays(VkCommandBuffer cb, const DeviceTraceFrame& frame);
  [[nodiscard]] bool record_engine_trace(VkCommandBuffer cb, const DeviceTraceFrame& frame, std::string* error);
  void record_resolve(VkCommandBuffer cb, const DeviceTraceFrame& frame);

  GpuReconstructor& owner_;
  VkDevice device_ = VK_NULL_HANDLE;
  const foveation::PointSet* uploaded_points_ = nullptr;
  std::uint32_t ray_capacity_ = 0;
  BoundBuffer points_, staging_, rays_, point_index_, ray_colors_, control_, status_;
  VkDeviceSize staged_bytes_ = 0;    // points waiting in staging_ for the next record
  std::uint64_t uploaded_bytes_ = 0;  // the last record's copy of them
  VkDescriptorPool pool_ = VK_NULL_HANDLE;
  VkDescriptorSet rays_set_ = VK_NULL_HANDLE, resolve_set_ = VK_NULL_HANDLE;
  VkBuffer bound_colors_ = VK_NULL_HANDLE, bound_point_depth_ = VK_NULL_HANDLE;
  bool descriptors_stale_ = true;
  XrResult engine_result_ = XR_SUCCESS;
};

}  // namespace foveart::layer
