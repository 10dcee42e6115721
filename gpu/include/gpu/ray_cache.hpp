// The render cache on the GPU (shaders/cache_*.comp, shaders/ray_cache.glsl;
// docs/gpu.md "The render cache"): the twin of foveation::RayCache as
// foveation::RayHistory runs it on the CPU. Its kept rays
// live on the device only; per frame the host uploads the frame's new rays
// (32 bytes each) and 8 bytes per pixel: the footprint each pixel filters
// at and the distance beyond which a kept ray there is covered, both as
// foveation::RayHistory decides them for either path (TemporalFrame::ray_pixels).
//
// Memory: 104 bytes per ray the frame holds (its kept and its new rays), in
// buffers grown by half again whenever a frame needs more, the kept rays
// copied over: about max_age_frames x the rays a frame traces (RayCacheOptions).
//
// Threads: as Eye (one thread at a time). The kept count is read back from
// the last submission, so each frame's submission must have finished before
// the next record (the layer waits for it in xrEndFrame). Nothing here throws.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <vulkan/vulkan.h>

#include "foveation/executor.hpp"
#include "foveation/ray_cache.hpp"
#include "foveation/ray_trace.h"
#include "gpu/context.hpp"
#include "gpu/vk_util.hpp"

namespace foveart::gpu {

// What one eye's frame gives the cache (foveation::FrameHandOff: the traced
// rays, and the ray history's pixels and restart).
struct RayCacheFrame {
  const std::vector<std::vector<foveation::TracedRay>>* rays = nullptr;
  const std::vector<glm::vec2>* pixels = nullptr;  // per screen pixel: footprint, covering distance
  bool restart = true;                             // forget every kept ray first
  foveation::PixelFilter filter = foveation::PixelFilter::box;
  std::uint32_t max_age_frames = 32;  // 0: no limit
};

// The pipelines, shared by the eyes of one device.
class RayCachePipelines {
 public:
  static std::unique_ptr<RayCachePipelines> create(VkDevice device, std::string* error);
  ~RayCachePipelines();
  RayCachePipelines(const RayCachePipelines&) = delete;
  RayCachePipelines& operator=(const RayCachePipelines&) = delete;

  VkDescriptorSetLayout set_layout() const { return set_layout_; }
  VkPipelineLayout layout() const { return layout_; }
  VkPipeline rays() const { return rays_; }
  VkPipeline scan() const { return scan_; }
  VkPipeline bin() const { return bin_; }
  VkPipeline filter() const { return filter_; }

 private:
  RayCachePipelines() = default;
  VkDevice device_ = VK_NULL_HANDLE;
  VkDescriptorSetLayout set_layout_ = VK_NULL_HANDLE;
  VkPipelineLayout layout_ = VK_NULL_HANDLE;
  VkPipeline rays_ = VK_NULL_HANDLE, scan_ = VK_NULL_HANDLE, bin_ = VK_NULL_HANDLE, filter_ = VK_NULL_HANDLE;
};

// One eye's cache.
class RayCache {
 public:
  // `current`: the eye's gather (one vec4 per pixel), which the cache's frame
  // overwrites; max_buffer_bytes: the largest buffer (0: the device's maxStorageBufferRange).
  RayCache(const Context& context, const RayCachePipelines& pipelines, VkBuffer current, std::uint32_t width_px,
           std::uint32_t height_px, VkDeviceSize max_buffer_bytes = 0);
  ~RayCache();
  RayCache(const RayCache&) = delete;
  RayCache& operator=(const RayCache&) = delete;

  // Writes the frame's rays and pixels into the upload buffers and records
  // the cache's passes into `cb`: they read the gather in `current` (the
  // eye's, one vec4 per pixel) and write the frame over it where a ray
  // reaches. Leaves `cb` with the cache's pipeline layout bound.
  [[nodiscard]] bool record(VkCommandBuffer cb, const RayCacheFrame& frame, const FoveartEyeView& view,
              foveation::Executor& executor, std::string* error);
  // The rays kept after the last finished submission.
  std::size_t kept_rays() const;

 private:
  using Buffer = BoundBuffer;
  // Room for `kept` + `added` rays and `added` new ones; a larger buffer gets
  // the kept rays copied in `cb`, the old ones are destroyed at the next record.
  [[nodiscard]] bool ensure_capacity(VkCommandBuffer cb, std::size_t kept, std::size_t added, std::string* error);
  bool update_descriptors(std::string* error);
  [[nodiscard]] bool make(Buffer& b, VkDeviceSize size, bool host_visible, std::string* error);
  void destroy(Buffer& b);

  const Context& context_;
  const RayCachePipelines& pipelines_;
  VkDevice device_ = VK_NULL_HANDLE;
  VkDeviceSize max_buffer_bytes_ = 0;  // maxStorageBufferRange
  VkBuffer current_ = VK_NULL_HANDLE;
  std::uint32_t width_px_ = 0, height_px_ = 0, cells_x_ = 0, cells_y_ = 0;
  std::size_t capacity_ = 0, new_capacity_ = 0;
  Buffer anchors_[2], new_rays_, ray_frame_, cells_, by_cell_, pixels_, counter_;
  std::vector<Buffer> retired_;  // replaced by larger ones; the submission in flight may still read them
  VkDescriptorPool pool_ = VK_NULL_HANDLE;
  VkDescriptorSet sets_[2] = {VK_NULL_HANDLE, VK_NULL_HANDLE};  // anchors 0 -> 1, 1 -> 0
  int parity_ = 0;             // which anchor buffer holds the kept rays
  bool recorded_ = false;      // a frame was recorded: the counter holds its kept rays
  bool descriptors_stale_ = false;  // a buffer was replaced since the sets were written
};

}  // namespace foveart::gpu
