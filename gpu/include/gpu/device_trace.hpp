// Stages 1-3 of a frame on the device, for an engine that traces on the GPU
// (docs/gpu.md "The device trace"; the layer adapts the app's
// XrFoveatedDeviceTraceInfoFOVEART to a DeviceTraceEngine):
// shaders/device_rays.comp selects the visible points and makes their rays
// from the gaze offset and the view (push constants) in the point set's order,
// the engine records its trace of them into the frame's command buffer, and
// shaders/device_resolve.comp averages each point's rays into the slots the
// gather reads. No ray or colour crosses to the host: the resolve's status
// (in the eye's frame slot) is read on the device by the frame's encode,
// which keeps the eye's last good image on a fault, and by the host frames later.
//
// Content density (DeviceTraceFrame::density, thesis 8.2) on the device: the
// rays pass thins points and varies their rays by the eye's tiles of the last
// frame's contrast (DeviceTraceTargets::tiles, which persist across frames);
// the resolve measures this frame's tiles from the traced colours, fills the
// thinned points from their parents and turns the tiles' ranges into the next
// frame's contrast (record_fill, record_contrast). Nothing waits on the host.
//
// Frames in flight (gpu/frame_slots.hpp): a DeviceTrace is one frame slot's
// set of buffers (rays, point index, colours, control, blocks, the point set
// and its staging copy) and descriptor sets; gpu::Eye keeps one per slot, so
// it is recorded again only after that slot's previous submission finished.
//
// Threads: as Eye (one thread at a time). Nothing here throws.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include <vulkan/vulkan.h>

#include "foveation/content_density.hpp"
#include "foveation/gaze_mapping.hpp"
#include "foveation/point_levels.hpp"
#include "foveation/point_set.hpp"
#include "foveation/ray_samples.hpp"
#include "foveation/ray_trace.h"
#include "gpu/context.hpp"
#include "gpu/vk_util.hpp"

namespace foveart::gpu {

// A range of one of the device trace's buffers.
struct BufferRange {
  VkBuffer buffer = VK_NULL_HANDLE;
  VkDeviceSize offset = 0;
  VkDeviceSize size = 0;  // bytes
};

// What the engine traces one view's rays from, and records its trace into:
// the contract of XrFoveatedDeviceRayBatchFOVEART (the layer's public header
// states it in full), without OpenXR.
struct DeviceRayBatch {
  std::uint64_t frame_index = 0;
  const FoveartEyeView* view = nullptr;
  std::uint32_t ray_capacity = 0;
  std::uint32_t rays_per_point = 1;  // the most a point casts (with content density, 1 to this; point_index says whose)
  BufferRange ray_count;    // XrFoveatedDeviceRayCountFOVEART (shader_interface/device_trace.h); read and indirect only
  BufferRange rays;         // ray_capacity x DeviceRay; read only
  BufferRange point_index;  // ray_capacity x uint32_t; read only
  BufferRange colors;       // ray_capacity x vec4 (rgb, depth_m); written by the engine
  BufferRange footprints;   // ray_capacity x float: each ray's footprint in radians (its point's disc); read only
  VkCommandBuffer command_buffer = VK_NULL_HANDLE;  // record the trace here
  // Each range's device address (buffer address + offset); all 0 unless Context::buffer_device_address().
  struct Addresses {
    VkDeviceAddress ray_count = 0, rays = 0, point_index = 0, colors = 0, footprints = 0;
  } addresses;
};

// The engine's device trace: records into batch.command_buffer; false when
// it failed (the frame is then not submitted; the caller keeps the engine's own result).
using DeviceTraceEngine = std::function<bool(const DeviceRayBatch& batch)>;

// What one eye's device-traced frame needs.
struct DeviceTraceFrame {
  DeviceTraceEngine engine;
  const foveation::PointSet* points = nullptr;  // the view tables' set
  FoveartEyeView view{};
  foveation::GazeMapping mapping;
  std::uint64_t frame_index = 0;
  std::uint64_t sample_seed = 0;
  std::uint32_t rays_per_point = 1;
  foveation::PixelFilter pixel_filter = foveation::PixelFilter::box;
  // The app-recorded trace: the rays were made earlier (Eye::record_app_rays)
  // and the app's submission traced them; the frame resolves only (engine unused).
  bool app_trace = false;
  // Content density (off by default); `levels`: the set's (ViewTables::levels) while on.
  foveation::ContentDensityOptions density;
  const foveation::PointLevels* levels = nullptr;
  // Content density runs: enabled, with the levels (the app-recorded trace's rays read the
  // tiles in the acquire's submission, after the last frame's in queue order).
  bool density_on() const { return density.enabled() && levels != nullptr; }
};

// What the resolve found (read after the submission finished).
struct DeviceTraceStatus {
  std::uint64_t invalid_components = 0;  // NaN, infinite or negative colour components
  std::uint32_t visible_points = 0;
  std::uint32_t traced_points = 0;   // visible and not thinned
  std::uint32_t thinned_points = 0;  // visible, thinned by content density (filled from their parents)
  std::uint64_t rays = 0;            // rays made for the engine
};

// The frame slot's buffers the resolve writes: every point's colour and depth
// (cleared by the caller), and the status (FOVEART_DEVICE_STATUS_WORDS words,
// cleared by the caller), which the frame's encode reads on the device; and
// the eye's content-density tiles (device_trace.h), which persist across frames.
struct DeviceTraceTargets {
  VkBuffer colors = VK_NULL_HANDLE, point_depth = VK_NULL_HANDLE, status = VK_NULL_HANDLE, tiles = VK_NULL_HANDLE;
  // The tiles may hold the last frame's contrast: the eye's last frame measured them and was recorded whole.
  bool tiles_measured = false;
  bool same_buffers(const DeviceTraceTargets& o) const {
    return colors == o.colors && point_depth == o.point_depth && status == o.status && tiles == o.tiles;
  }
};

// The buffers a frame's rays and hits are in, for a pass after the resolve
// (the render cache's cache_device_rays.comp reads them on the device).
struct DeviceTraceBuffers {
  VkBuffer rays = VK_NULL_HANDLE;         // DeviceRay per ray
  VkBuffer ray_colors = VK_NULL_HANDLE;   // vec4 per ray: rgb, depth in metres (the engine's)
  VkBuffer point_rays = VK_NULL_HANDLE;   // DevicePointRays per rank of a visible point, traced ones first
  VkBuffer control = VK_NULL_HANDLE;      // the control words (device_trace.h)
  VkBuffer status = VK_NULL_HANDLE;       // the resolve's status words
  VkBuffer points = VK_NULL_HANDLE;       // DevicePoint per point of the set
};

// Content density's tiles of tile_px on a width_px x height_px screen (ContentDensity's grid;
// device_density.glsl's density_tiles).
std::uint64_t device_tiles(std::uint32_t width_px, std::uint32_t height_px, std::uint32_t tile_px);
// Tiles per region of an eye's content-density tile words (shader_interface/device_trace.h):
// those of FOVEART_DEVICE_MIN_TILE_PX on the screen.
std::uint64_t device_tile_capacity(std::uint32_t width_px, std::uint32_t height_px);

// The device trace's shaders, shared by the eyes of one device.
class DeviceTracePipelines {
 public:
  static std::unique_ptr<DeviceTracePipelines> create(VkDevice device, std::string* error);
  ~DeviceTracePipelines();
  DeviceTracePipelines(const DeviceTracePipelines&) = delete;
  DeviceTracePipelines& operator=(const DeviceTracePipelines&) = delete;

  VkDescriptorSetLayout rays_set_layout() const { return rays_set_layout_; }
  VkDescriptorSetLayout resolve_set_layout() const { return resolve_set_layout_; }
  VkPipelineLayout rays_layout() const { return rays_layout_; }
  VkPipelineLayout resolve_layout() const { return resolve_layout_; }
  VkPipeline rays() const { return rays_; }
  VkPipeline resolve() const { return resolve_; }

 private:
  DeviceTracePipelines() = default;
  VkDevice device_ = VK_NULL_HANDLE;
  VkDescriptorSetLayout rays_set_layout_ = VK_NULL_HANDLE, resolve_set_layout_ = VK_NULL_HANDLE;
  VkPipelineLayout rays_layout_ = VK_NULL_HANDLE, resolve_layout_ = VK_NULL_HANDLE;
  VkPipeline rays_ = VK_NULL_HANDLE, resolve_ = VK_NULL_HANDLE;
};

// One eye's rays, colours and counts on the device.
class DeviceTrace {
 public:
  DeviceTrace(const Context& context, const DeviceTracePipelines& pipelines);
  ~DeviceTrace();
  DeviceTrace(const DeviceTrace&) = delete;
  DeviceTrace& operator=(const DeviceTrace&) = delete;

  // Records the frame's rays, the engine's trace and the resolve into `cb`,
  // writing every visible point's colour (a = 1) and depth, and the status,
  // into `targets`. false with *error when a buffer cannot be made or the
  // engine's trace fails (what was recorded stays in `cb`). The three steps
  // below in one command buffer: the device trace's callback model.
  [[nodiscard]] bool record(VkCommandBuffer cb, const DeviceTraceFrame& frame, const DeviceTraceTargets& targets,
                            std::string* error);
  // Stages 1-2: the frame's rays (and counts, and NaN colours) into this
  // trace's buffers; frame.engine is not called. false with *error when a
  // buffer cannot be made.
  [[nodiscard]] bool record_rays(VkCommandBuffer cb, const DeviceTraceFrame& frame, const DeviceTraceTargets& targets,
                                 std::string* error);
  // Stage 3's input and output: the buffers of the last record_rays, for an
  // engine recording into `cb` (VK_NULL_HANDLE: the app's own command buffer).
  DeviceRayBatch batch(const DeviceTraceFrame& frame, VkCommandBuffer cb) const;
  // After the engine's trace (in `cb` or a submission `cb`'s waits for): the
  // colours per point into the targets of the last record_rays (with content
  // density, also their luminance into the tiles' ranges, cleared first).
  void record_resolve(VkCommandBuffer cb, const DeviceTraceFrame& frame);
  // Content density, after the resolve (nothing when it is off): the thinned
  // points filled from their parents, then the tiles' contrast for the next frame.
  void record_fill(VkCommandBuffer cb, const DeviceTraceFrame& frame);
  void record_contrast(VkCommandBuffer cb, const DeviceTraceFrame& frame);
  // Bytes the host wrote for the last record: the point set, once per table set; else 0.
  std::uint64_t host_bytes_written() const { return uploaded_bytes_; }
  // The buffers the last record wrote the frame's rays, hits and status into
  // (the status is the slot's target, DeviceTraceTargets::status).
  DeviceTraceBuffers buffers() const {
    return {rays_.buffer, ray_colors_.buffer, point_rays_.buffer, control_.buffer, bound_.status, points_.buffer};
  }

 private:
  [[nodiscard]] bool ensure_buffers(const foveation::PointSet& points, std::uint32_t rays_per_point, std::string* error);
  [[nodiscard]] bool ensure_levels(const foveation::PointLevels* levels, std::string* error);
  void record_uploads(VkCommandBuffer cb);
  // Binds the resolve for `pass`; the caller dispatches it.
  void bind_resolve(VkCommandBuffer cb, const DeviceTraceFrame& frame, std::uint32_t pass);
  void update_descriptors(const DeviceTraceTargets& targets);
  // Stages 1-2's passes, and stage 3 by frame.engine into `cb`.
  void record_ray_passes(VkCommandBuffer cb, const DeviceTraceFrame& frame);
  [[nodiscard]] bool record_engine_trace(VkCommandBuffer cb, const DeviceTraceFrame& frame, std::string* error);

  const Context& context_;
  const DeviceTracePipelines& pipelines_;
  VkDevice device_ = VK_NULL_HANDLE;
  const foveation::PointSet* uploaded_points_ = nullptr;
  const foveation::PointLevels* uploaded_levels_ = nullptr;
  std::uint32_t ray_capacity_ = 0;
  BoundBuffer points_, staging_, rays_, point_index_, ray_colors_, control_;
  BoundBuffer footprints_;  // per ray: its point's disc radius as an angle, radians (device_rays.comp)
  BoundBuffer blocks_;      // per block of points: its rays, traced and thinned points, then where they begin
  BoundBuffer point_rays_;  // per rank of a visible point: DevicePointRays (device_rays.comp), traced ones first
  BoundBuffer levels_, levels_staging_;  // per point: DeviceLevel (content density; a placeholder while off)
  VkDeviceSize staged_bytes_ = 0;    // points waiting in staging_ for the next record
  VkDeviceSize staged_level_bytes_ = 0;  // levels waiting in levels_staging_
  std::uint64_t uploaded_bytes_ = 0;  // the last record's copy of them
  VkDescriptorPool pool_ = VK_NULL_HANDLE;
  VkDescriptorSet rays_set_ = VK_NULL_HANDLE, resolve_set_ = VK_NULL_HANDLE;
  DeviceTraceTargets bound_;
  bool descriptors_stale_ = true;
};

}  // namespace foveart::gpu
