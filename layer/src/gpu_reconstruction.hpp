// Reconstruction, temporal history and sRGB encode of one eye on the app's Vulkan device
// (shaders/, docs/gpu.md): the GPU path of the layer's frame. The CPU path
// (foveation::gather, TemporalAccumulator, encode_rgba8) is its reference;
// outputs agree within one 8-bit step (tests/layer/gpu_reconstruction_test.cpp).
//
// Per frame only the traced points' colours (16 bytes each) go to the device;
// tables are uploaded once per ViewTables into device-local chunks
// (gpu_tables.hpp). Recording happens on the caller's command buffer; the
// caller submits it on the app's queue inside xrEndFrame and waits for it.
//
// Threads: one GpuReconstructor per device, used from one thread at a time
// (the renderer's frame lock). Nothing here throws; failures return false
// with a message.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "foveation/display_transform.hpp"
#include "foveation/executor.hpp"
#include "foveation/foveated_view.hpp"
#include "gpu_device_trace.hpp"
#include "gpu_ray_cache.hpp"
#include "gpu_tables.hpp"

namespace foveart::layer {

struct GpuDevice {
  VkPhysicalDevice physical_device = VK_NULL_HANDLE;
  VkDevice device = VK_NULL_HANDLE;
  uint32_t queue_family_index = 0;
  uint32_t queue_index = 0;
};

// Why the shaders cannot run on this device's queue family; empty when they can.
std::string gpu_unsupported_reason(VkPhysicalDevice physical_device, uint32_t queue_family_index);

class GpuReconstructor;

// One view's tables on the device, shared by both eyes.
class GpuTables {
 public:
  ~GpuTables();
  GpuTables(const GpuTables&) = delete;
  GpuTables& operator=(const GpuTables&) = delete;
  const GpuTablePack& layout() const { return pack_; }  // chunk words are dropped after upload
  const foveation::ViewTables& view_tables() const { return *tables_; }
  std::size_t bytes() const { return bytes_; }

 private:
  friend class GpuReconstructor;
  friend class GpuEye;
  GpuTables() = default;
  VkDevice device_ = VK_NULL_HANDLE;
  std::shared_ptr<const foveation::ViewTables> tables_;
  GpuTablePack pack_;
  std::vector<VkBuffer> buffers_;
  std::vector<VkDeviceMemory> memory_;
  std::size_t bytes_ = 0;
};

// What one eye's frame reconstructs.
struct GpuFrame {
  const GpuTables* tables = nullptr;
  const foveation::PointColors* colors = nullptr;  // the view's colours this frame (a = 1 traced)
  const std::vector<float>* point_depth_m = nullptr;  // per point (NaN: none; +inf: sky); null: no depth
  std::span<const std::vector<std::uint32_t>> traced;  // the points traced this frame, in runs
  foveation::GazeMapping mapping;
  foveation::RbfClamp rbf_clamp = foveation::RbfClamp::block;
  std::array<float, 3> fallback_rgb{};
  bool temporal_reset = true;  // the history restarts: the output is this frame alone (always without a history)
  FoveartEyeView view{};  // this frame's view
  std::optional<FoveartEyeView> history_view;  // set: reproject the history from this view (TemporalFrame)
  foveation::TemporalOptions blend;  // current_weight: this frame's blend weight (TemporalFrame::blend)
  bool srgb = true;       // sRGB-encode (an sRGB swapchain format)
  foveation::DisplayTransform display;  // exposure and tone-mapping curve before the encode
  // Set: the view's history is a render cache (TemporalMode::rays), which
  // replaces the image history: this frame's rays and pixels for it.
  std::optional<GpuRayCacheFrame> ray_cache;
  // Set: stages 1-3 run on the device (the engine's device trace); colors,
  // point_depth_m and traced are then not read.
  const DeviceTraceFrame* device = nullptr;

  // A frame's hand-off (FoveatedView::hand_off after render() with
  // reconstruct_on_cpu = false), on `tables`: the traced points and the
  // temporal history's decision.
  static GpuFrame of(const GpuTables& tables, const foveation::FrameHandOff& frame, bool srgb);
};

// GPU time of each stage of the last frame (timestamps), milliseconds.
struct GpuStageTimes {
  // temporal_ms: the image history, or the render cache with its copy into the output.
  // scatter_ms: on a device-traced frame, the rays, the engine's trace and the resolve.
  float scatter_ms = 0, gather_ms = 0, temporal_ms = 0, encode_ms = 0;  // encode includes the copy into the image
  float total_ms() const { return scatter_ms + gather_ms + temporal_ms + encode_ms; }
};

// One eye's buffers (colours, reconstruction, temporal history, RGBA8) and descriptor sets.
class GpuEye {
 public:
  ~GpuEye();
  GpuEye(const GpuEye&) = delete;
  GpuEye& operator=(const GpuEye&) = delete;

  // Writes the traced colours into the upload buffer and records the frame
  // into `cb`: scatter, gather, temporal blend (or the render cache), encode, and (image != null) the copy
  // into `image`, left in COLOR_ATTACHMENT_OPTIMAL as OpenXR requires at release.
  [[nodiscard]] bool record(VkCommandBuffer cb, const GpuFrame& frame, VkImage image, foveation::Executor& executor,
              std::string* error);
  // After the submission finished: the stage times it measured.
  bool stage_times(GpuStageTimes* out) const;
  // After the submission finished: records nothing; copies the last frame's RGBA8 texels (tests, benchmarks).
  [[nodiscard]] bool read_rgba8(std::vector<std::uint8_t>* out, std::string* error);

  // After a device-traced submission finished: what its resolve found; the
  // engine's answer to its last call (XR_SUCCESS when it was not called).
  DeviceTraceStatus device_trace_status() const;
  XrResult device_trace_result() const;
  // Bytes the host wrote into, and read from, mapped memory for the last
  // frame (uploads, status and timestamp read-backs; push constants aside).
  std::uint64_t host_bytes_written() const;
  std::uint64_t host_bytes_read() const;

  // The render cache's rays kept after the last finished submission (0: no cache).
  std::size_t cached_rays() const { return ray_cache_ != nullptr ? ray_cache_->kept_rays() : 0; }

  uint32_t width_px() const { return width_px_; }
  uint32_t height_px() const { return height_px_; }

 private:
  friend class GpuReconstructor;
  GpuEye() = default;
  using Buffer = BoundBuffer;
  [[nodiscard]] bool ensure_points(std::size_t point_count, std::string* error);
  // The frame's stages 4-6 (foveation/frame_stages.hpp), recorded in turn by record().
  [[nodiscard]] bool record_reconstruct(VkCommandBuffer cb, const GpuFrame& frame, foveation::Executor& executor,
                          std::string* error);
  [[nodiscard]] bool record_temporal(VkCommandBuffer cb, const GpuFrame& frame, VkDescriptorSet set, foveation::Executor& executor,
                       std::string* error);
  void record_encode(VkCommandBuffer cb, const GpuFrame& frame, VkImage image);
  void stamp(VkCommandBuffer cb, uint32_t query) const;  // a timestamp, when the queue has them
  void update_descriptors();
  void destroy(Buffer& b);

  GpuReconstructor* owner_ = nullptr;
  VkDevice device_ = VK_NULL_HANDLE;
  uint32_t width_px_ = 0, height_px_ = 0;
  Buffer upload_, colors_, point_depth_, current_, history_[2], encoded_, readback_;
  std::size_t point_capacity_ = 0;
  const GpuTables* bound_tables_ = nullptr;
  VkDescriptorPool pool_ = VK_NULL_HANDLE;
  VkDescriptorSet sets_[2] = {VK_NULL_HANDLE, VK_NULL_HANDLE};  // history 0 -> 1, 1 -> 0
  int parity_ = 0;                                              // which set the last frame used
  VkQueryPool queries_ = VK_NULL_HANDLE;
  bool recorded_ = false;
  std::unique_ptr<GpuRayCache> ray_cache_;  // made by the first frame with one
  std::unique_ptr<GpuDeviceTrace> device_trace_;  // made by the first device-traced frame
  std::uint64_t host_written_ = 0;
  mutable std::uint64_t host_read_ = 0;
};

class GpuReconstructor {
 public:
  // Null with *error when the device cannot run the shaders (gpu_unsupported_reason) or a Vulkan call fails.
  static std::unique_ptr<GpuReconstructor> create(const GpuDevice& device, std::string* error);
  ~GpuReconstructor();
  GpuReconstructor(const GpuReconstructor&) = delete;
  GpuReconstructor& operator=(const GpuReconstructor&) = delete;

  // Packs and uploads `tables` (submits and waits on the device's queue) in
  // buffers of at most max_chunk_bytes (0: the device's maxStorageBufferRange).
  std::shared_ptr<GpuTables> upload_tables(std::shared_ptr<const foveation::ViewTables> tables, std::string* error,
                                           std::size_t max_chunk_bytes = 0);
  std::unique_ptr<GpuEye> create_eye(uint32_t width_px, uint32_t height_px, std::string* error);

  // Records with `record` into a one-time command buffer, submits it on the
  // queue and waits (table uploads, tests, benchmarks; the layer uses its swapchain's).
  [[nodiscard]] bool submit_and_wait(const std::function<bool(VkCommandBuffer)>& record, std::string* error);

  VkDeviceSize max_chunk_bytes() const { return max_chunk_bytes_; }
  const GpuDevice& device() const { return device_; }

 private:
  friend class GpuEye;
  friend class GpuDeviceTrace;
  GpuReconstructor() = default;
  [[nodiscard]] bool create_buffer(VkDeviceSize size, VkBufferUsageFlags usage, bool host_visible, VkBuffer* buffer,
                     VkDeviceMemory* memory, void** mapped, std::string* error);

  GpuDevice device_;
  VkQueue queue_ = VK_NULL_HANDLE;
  VkPhysicalDeviceMemoryProperties memory_properties_{};
  VkDeviceSize max_chunk_bytes_ = 0;
  VkDeviceSize storage_alignment_ = 4;
  float timestamp_period_ns_ = 1.0f;
  bool timestamps_ = false;
  VkDescriptorSetLayout set_layout_ = VK_NULL_HANDLE;
  VkPipelineLayout pipeline_layout_ = VK_NULL_HANDLE;
  VkPipeline scatter_ = VK_NULL_HANDLE, gather_ = VK_NULL_HANDLE, temporal_ = VK_NULL_HANDLE, encode_ = VK_NULL_HANDLE;
  std::unique_ptr<GpuRayCachePipelines> ray_cache_;
  std::unique_ptr<GpuDeviceTracePipelines> device_trace_;
  VkCommandPool command_pool_ = VK_NULL_HANDLE;
  VkCommandBuffer command_buffer_ = VK_NULL_HANDLE;
  VkFence fence_ = VK_NULL_HANDLE;
};

}  // namespace foveart::layer
