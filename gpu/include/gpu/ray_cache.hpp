// The render cache on the GPU (shaders/cache_*.comp, shaders/ray_cache.glsl;
// docs/gpu.md "The render cache"): the twin of foveation::RayCache as
// foveation::RayHistory runs it on the CPU. Its kept rays and their count
// live on the device only; nothing is read back on the frame path. Per frame
// either the host uploads the frame's new rays (32 bytes each) and 8 bytes per
// pixel (the footprint each pixel filters at and the distance beyond which a
// kept ray there is covered, as foveation::RayHistory decides them:
// TemporalFrame::ray_pixels), or, with a device trace, cache_device_rays and
// cache_pixels make both on the device from the trace's rays and hits and the
// view's tables, by the same rule. cache_count turns the kept count into the
// indirect dispatch of the per-ray passes.
//
// Frames in flight: the buffers the host writes (new rays, pixels) exist once
// per frame slot, as do the descriptor sets; the kept rays, the counts and
// the passes' scratch are shared, ordered by the queue (the eye's barrier at
// the top of each frame covers the earlier submission). The host sizes the
// buffers from a bound it knows: the kept rays are at most the rays added in
// the last max_age_frames frames (a device trace's: its point set's size x
// rays per point). Where that would not fit the device's
// maxStorageBufferRange the cache keeps fewer frames (a shorter age limit
// for that frame); a frame whose new rays alone do not fit fails.
//
// Memory: 104 bytes per ray the bound holds, in buffers grown by half again
// when short, the kept rays copied over.
//
// Threads: as Eye (one thread at a time). A slot is recorded again only after
// its last submission finished (kFrameSlots frames later). Nothing here throws.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <vulkan/vulkan.h>

#include "foveation/executor.hpp"
#include "foveation/ray_cache.hpp"
#include "foveation/ray_trace.h"
#include "gpu/context.hpp"
#include "gpu/device_trace.hpp"
#include "gpu/frame_slots.hpp"
#include "gpu/shader_interface/cache_push.h"
#include "gpu/tables.hpp"
#include "gpu/vk_util.hpp"

namespace foveart::gpu {

// A device-traced frame's rays as the cache reads them on the device.
struct RayCacheDeviceRays {
  DeviceTraceBuffers trace;               // the frame's rays, hits, counts and status
  VkBuffer point_colors = VK_NULL_HANDLE;  // the eye's colour slots (a = traced), after the resolve
  const Tables* tables = nullptr;          // the view's tables (their chunks give each pixel's neighbours)
  foveation::GazeMapping mapping;
  std::uint32_t rays_per_point = 1;        // at most, per point (content density may cast fewer)
  bool thins = false;                      // content density thins points (they cast no ray)
};

// What one eye's frame gives the cache (foveation::FrameHandOff: the traced
// rays, and the ray history's pixels and restart; or the device trace's).
struct RayCacheFrame {
  const std::vector<std::vector<foveation::TracedRay>>* rays = nullptr;
  const std::vector<glm::vec2>* pixels = nullptr;  // per screen pixel: footprint, covering distance
  std::optional<RayCacheDeviceRays> device;         // set: rays and pixels come from the device, not the two above
  bool restart = true;                             // forget every kept ray first
  foveation::PixelFilter filter = foveation::PixelFilter::box;
  std::uint32_t max_age_frames = 32;  // 0: no limit
};

// The pipelines, shared by the eyes of one device: the passes over the
// cache's own set, and the two that read a device trace's frame.
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
  VkPipeline count() const { return count_; }
  VkDescriptorSetLayout device_rays_set_layout() const { return device_rays_set_layout_; }
  VkPipelineLayout device_rays_layout() const { return device_rays_layout_; }
  VkPipeline device_rays() const { return device_rays_; }
  VkDescriptorSetLayout pixels_set_layout() const { return pixels_set_layout_; }
  VkPipelineLayout pixels_layout() const { return pixels_layout_; }
  VkPipeline pixels() const { return pixels_; }

 private:
  RayCachePipelines() = default;
  VkDevice device_ = VK_NULL_HANDLE;
  VkDescriptorSetLayout set_layout_ = VK_NULL_HANDLE, device_rays_set_layout_ = VK_NULL_HANDLE,
                        pixels_set_layout_ = VK_NULL_HANDLE;
  VkPipelineLayout layout_ = VK_NULL_HANDLE, device_rays_layout_ = VK_NULL_HANDLE, pixels_layout_ = VK_NULL_HANDLE;
  VkPipeline rays_ = VK_NULL_HANDLE, scan_ = VK_NULL_HANDLE, bin_ = VK_NULL_HANDLE, filter_ = VK_NULL_HANDLE,
             count_ = VK_NULL_HANDLE, device_rays_ = VK_NULL_HANDLE, pixels_ = VK_NULL_HANDLE;
};

// One eye's cache.
class RayCache {
 public:
  // `current`: the eye's gather (one vec4 per pixel), which the cache's frame
  // overwrites; `slots`: frames in flight (kFrameSlots); max_buffer_bytes:
  // the largest buffer (0: the device's maxStorageBufferRange).
  RayCache(const Context& context, const RayCachePipelines& pipelines, VkBuffer current, std::uint32_t width_px,
           std::uint32_t height_px, std::uint32_t slots = kFrameSlots, VkDeviceSize max_buffer_bytes = 0);
  ~RayCache();
  RayCache(const RayCache&) = delete;
  RayCache& operator=(const RayCache&) = delete;

  // Records frame `frame` of slot `slot` (< slots) into `cb`: the callback's
  // rays and pixels written into the slot's upload buffers, or the device
  // trace's made into them on the device, then the cache's passes: they read
  // the gather in `current` and write the frame over it where a ray reaches.
  // Leaves `cb` with the cache's pipeline layout bound. False with *error
  // (and the cache as it was) when the frame's rays cannot fit.
  [[nodiscard]] bool record(VkCommandBuffer cb, const RayCacheFrame& frame, const FoveartEyeView& view,
                            std::uint32_t slot, foveation::Executor& executor, std::string* error);
  // Tests and benchmarks only, never on the frame path: the rays kept after
  // the last recorded frame, read back from the device with a submission of
  // its own on `context`, after the caller waited for that frame. False with *error.
  [[nodiscard]] bool kept_rays_after_wait(Context& context, std::size_t* kept, std::string* error);

 private:
  using Buffer = BoundBuffer;
  struct SlotBuffers {  // what the host writes per frame slot
    Buffer new_rays, pixels;
    std::size_t new_capacity = 0;
  };
  struct Frame;  // one record's sizes and push constants
  // The rays the anchors hold this frame, and the age limit that keeps the next within the device's range.
  [[nodiscard]] bool plan_frame(const RayCacheFrame& frame, std::size_t added, Frame* out, std::string* error);
  // Room for `rays` rays in the anchors and `added` new ones in `upload`.
  [[nodiscard]] bool ensure_capacity(VkCommandBuffer cb, std::size_t rays, std::size_t added, SlotBuffers& upload,
                                     bool host_visible, std::string* error);
  [[nodiscard]] bool ensure_fixed(std::string* error);  // per eye: sized by the image
  [[nodiscard]] bool ensure_points(std::size_t point_count, std::string* error);  // a device trace's per point
  [[nodiscard]] bool grow_anchors(VkCommandBuffer cb, std::size_t rays, std::string* error);
  [[nodiscard]] bool make_sets(std::string* error);
  void write_upload(const RayCacheFrame& frame, SlotBuffers& upload, foveation::Executor& executor) const;
  void set_push(const RayCacheFrame& frame, const FoveartEyeView& view, std::size_t added,
                shader::CachePush& push) const;
  // Set `index` naming `buffers`; the cache's set of this slot and parity.
  VkDescriptorSet set_naming(std::size_t index, std::vector<VkBuffer> buffers, const std::uint32_t* counts,
                             std::uint32_t bindings);
  VkDescriptorSet cache_set(std::uint32_t slot, const RayCacheFrame& frame);
  void record_device_inputs(VkCommandBuffer cb, const RayCacheDeviceRays& device, std::uint32_t filter_kind,
                            std::uint32_t slot);
  void record_passes(VkCommandBuffer cb, const Frame& f, VkDescriptorSet set);
  [[nodiscard]] bool make(Buffer& b, VkDeviceSize size, bool host_visible, std::string* error) const;
  void retire(Buffer& b);
  void destroy(Buffer& b) const;

  const Context& context_;
  const RayCachePipelines& pipelines_;
  VkDevice device_ = VK_NULL_HANDLE;
  VkDeviceSize max_buffer_bytes_ = 0;  // maxStorageBufferRange
  VkBuffer current_ = VK_NULL_HANDLE;
  std::uint32_t width_px_ = 0, height_px_ = 0, cells_x_ = 0, cells_y_ = 0, slots_ = 1;
  std::size_t capacity_ = 0;
  Buffer anchors_[2], ray_frame_, cells_, by_cell_, counts_, readback_;
  std::vector<SlotBuffers> uploads_;  // per slot: the callback's rays and pixels
  SlotBuffers device_upload_;         // a device trace's: written on the device
  Buffer point_farthest_, drawn_;     // a device trace's farthest hits per point and per drawn pixel
  std::size_t point_capacity_ = 0;
  // Replaced by larger ones, destroyed once every submission that may read them finished.
  std::vector<std::pair<Buffer, std::uint64_t>> retired_;
  std::uint64_t records_ = 0;  // frames recorded
  VkDescriptorPool pool_ = VK_NULL_HANDLE;
  // Per slot: the cache's two (anchors 0 -> 1, 1 -> 0), cache_device_rays', cache_pixels'.
  std::vector<VkDescriptorSet> sets_;
  std::vector<std::vector<VkBuffer>> written_;  // the buffers each set names
  int parity_ = 0;  // which anchor buffer holds the kept rays
  // The host's bound on the rays each earlier frame added since the last
  // restart, newest last: the kept rays' bound.
  std::deque<std::size_t> added_bound_;
};

}  // namespace foveart::gpu
