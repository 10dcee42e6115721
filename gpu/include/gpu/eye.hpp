// One eye's frame on the device after the trace (docs/gpu.md): stage 4
// (scatter of the traced colours, the gather), stage 5 (the image history, or
// the render cache) and stage 6 (display transform and encode), and with a
// device trace stages 1-3 before them (device_trace.hpp). The CPU path
// (foveation::gather, TemporalAccumulator, encode_rgba8) is its reference;
// outputs agree within one 8-bit step (tests/gpu/reconstruction_test.cpp).
//
// Per frame only the traced points' colours (20 bytes each) go to the device
// (nothing with a device trace). Recording happens on the caller's command
// buffer, which the caller submits: a stage at a time by the device's stage
// set (device_stages.hpp, the layer's frames), or all at once by record()
// from a frame's hand-off (tests, benchmarks).
//
// Frames in flight (gpu/frame_slots.hpp): frame n is recorded into slot
// EyeFrame::slot = n % kFrameSlots. What a frame writes and the host fills or
// reads (upload, colours, point depths, the status, timestamps, the device
// trace's buffers) and the descriptor sets naming them exist once per slot;
// a slot is recorded again only after its previous submission finished. The
// image history pair, the gather's output (`current`, which the render cache
// binds) and the shown image are one per eye: frames run in queue order, and a
// barrier at the top of each frame's commands orders them after the previous
// submission. The render cache (ray_cache.hpp) keeps its count on the device
// and its uploads per slot: nothing is read back on the frame path.
//
// Faults on the device: the status (zeroed per frame; a device trace's
// resolve counts invalid colours into it) is read by the temporal pass, which
// then keeps the history as it was, and by the encode, which then leaves the
// shown image (the last good frame's) as it was; the copy into the swapchain
// image always copies the shown image. The host reads the status frames later.
//
// Threads: one thread at a time (the renderer's frame lock). Nothing here
// throws; failures return false with a message.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "foveation/display_transform.hpp"
#include "foveation/executor.hpp"
#include "foveation/foveated_view.hpp"
#include "gpu/context.hpp"
#include "gpu/device_trace.hpp"
#include "gpu/frame_pipelines.hpp"
#include "gpu/frame_slots.hpp"
#include "gpu/ray_cache.hpp"
#include "gpu/tables.hpp"

namespace foveart::gpu {

// What one eye's frame reconstructs.
struct EyeFrame {
  const Tables* tables = nullptr;
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
  std::optional<RayCacheFrame> ray_cache;
  // Set: stages 1-3 run on the device (the engine's device trace); colors,
  // point_depth_m and traced are then not read.
  const DeviceTraceFrame* device = nullptr;
  std::uint32_t slot = 0;  // the frame slot, < kFrameSlots: frame n's is n % kFrameSlots

  // A frame's hand-off (FoveatedView::hand_off after render() with
  // reconstruct_on_cpu = false), on `tables`: the traced points and the
  // temporal history's decision.
  static EyeFrame of(const Tables& tables, const foveation::FrameHandOff& frame, bool srgb);
  // Stage 5's decision for this frame: the history's blend and view, or the render cache's frame.
  void set_temporal(const foveation::TracedPoints& points, const foveation::TemporalFrame& temporal);
};

// GPU time of each stage of a frame (timestamps), milliseconds.
struct StageTimes {
  // start, traced, scattered, gathered, accumulated, encoded; within the trace: density fill, contrast, end
  static constexpr uint32_t kTimestamps = 9;
  float trace_ms = 0;     // a device-traced frame's rays, the engine's trace and the resolve (else 0)
  // Within trace_ms, content density's passes after the resolve (0 while off): the thinned
  // points filled from their parents, and the tiles' contrast for the next frame.
  float density_fill_ms = 0;
  float density_contrast_ms = 0;
  float scatter_ms = 0;   // the slots cleared and the uploaded colours scattered into them
  float gather_ms = 0;
  float temporal_ms = 0;  // the image history, or the render cache with its copy into the output
  float encode_ms = 0;    // includes the copy into the image
  float total_ms() const { return trace_ms + scatter_ms + gather_ms + temporal_ms + encode_ms; }
};

// One eye's buffers (colours, reconstruction, temporal history, RGBA8), descriptor sets and stages.
class Eye {
 public:
  static std::unique_ptr<Eye> create(Context& context, const FramePipelines& pipelines, uint32_t width_px,
                                     uint32_t height_px, std::string* error);
  ~Eye();
  Eye(const Eye&) = delete;
  Eye& operator=(const Eye&) = delete;

  // Writes the traced colours into the slot's upload buffer and records the
  // frame into `cb`: (the device trace,) scatter, gather, temporal blend (or
  // the render cache), encode into the shown image unless the status says the
  // trace failed, and (image != null) the copy of the shown image into
  // `image`, left in COLOR_ATTACHMENT_OPTIMAL as OpenXR requires at release.
  // The slot's previous submission must have finished. On false, what was
  // recorded stays in `cb` (it may be submitted: it writes only this eye's buffers).
  [[nodiscard]] bool record(VkCommandBuffer cb, const EyeFrame& frame, VkImage image, foveation::Executor& executor,
                            std::string* error);

  // The same frame a stage at a time (the device's stage set, device_stages.hpp):
  // begin_frame (the slot, its buffers and sets, the status cleared), the
  // stages in order as far as `frame` is known by then, end_frame.
  [[nodiscard]] bool begin_frame(VkCommandBuffer cb, const EyeFrame& frame, std::string* error);
  std::size_t upload_traced(const EyeFrame& frame, foveation::Executor& executor);  // CPU-traced colours, before 1-3
  [[nodiscard]] bool record_trace(VkCommandBuffer cb, const EyeFrame& frame, std::string* error);  // 1-3
  void record_scatter(VkCommandBuffer cb, const EyeFrame& frame, std::size_t uploaded);           // 4
  void record_gather(VkCommandBuffer cb, const EyeFrame& frame);                                  // 4
  [[nodiscard]] bool record_temporal(VkCommandBuffer cb, const EyeFrame& frame, foveation::Executor& executor,
                                     std::string* error);                                          // 5
  void record_encode(VkCommandBuffer cb, const EyeFrame& frame, VkImage image);                   // 6
  void end_frame();
  // The app-recorded trace: stages 1-2 of the frame in slot `slot_index` into
  // `cb` (submitted before the frame's record), and the buffers the app's
  // trace reads and writes. The frame's record() with device->app_trace then
  // resolves them. The slot's previous submission must have finished.
  [[nodiscard]] bool record_app_rays(VkCommandBuffer cb, std::uint32_t slot_index, const Tables& tables,
                                     const DeviceTraceFrame& frame, DeviceRayBatch* out_batch, std::string* error);
  // After the slot's submission finished: the stage times it measured.
  bool stage_times(std::uint32_t slot, StageTimes* out) const;
  bool stage_times(StageTimes* out) const { return stage_times(last_slot_, out); }
  // After the submission finished: records nothing; copies the shown image's
  // RGBA8 texels (tests, benchmarks).
  [[nodiscard]] bool read_rgba8(std::vector<std::uint8_t>* out, std::string* error);
  // After the slot's submission finished: records nothing; copies the point
  // colours (rgba per point, a = 1 traced or filled) the slot's frame resolved (tests).
  [[nodiscard]] bool read_point_colors(std::uint32_t slot, std::vector<float>* rgba, std::string* error);

  // After the slot's device-traced submission finished: what its resolve found.
  DeviceTraceStatus device_trace_status(std::uint32_t slot) const;
  DeviceTraceStatus device_trace_status() const { return device_trace_status(last_slot_); }
  // Bytes the host wrote into, and read from, mapped memory for the last
  // frame (uploads, status and timestamp read-backs; push constants aside).
  std::uint64_t host_bytes_written() const { return host_written_; }
  std::uint64_t host_bytes_read() const { return host_read_; }

  // Tests and benchmarks only: the render cache's rays kept after the last
  // frame, read back with a submission of its own after the caller waited
  // for that frame (0: no cache; SIZE_MAX: the read-back failed).
  std::size_t cached_rays_after_wait();

  uint32_t width_px() const { return width_px_; }
  uint32_t height_px() const { return height_px_; }

 private:
  // What commands submitted earlier on the queue wrote or read (shader or transfer), for this command buffer's.
  static void after_earlier_submissions(VkCommandBuffer cb);
  // What one frame slot holds (frame_slots.hpp).
  struct Slot {
    BoundBuffer upload, colors, point_depth, status;
    std::size_t point_capacity = 0;
    const Tables* bound_tables = nullptr;  // the tables the sets name (null: stale)
    VkDescriptorSet sets[2] = {VK_NULL_HANDLE, VK_NULL_HANDLE};  // history 0 -> 1, 1 -> 0
    VkQueryPool queries = VK_NULL_HANDLE;
    std::unique_ptr<DeviceTrace> device_trace;  // made by the slot's first device-traced frame
    bool recorded = false;
    bool density = false;  // its frame ran content density's passes: it measures the tiles, its times are kept
  };

  Eye(Context& context, const FramePipelines& pipelines, uint32_t width_px, uint32_t height_px);
  [[nodiscard]] bool create_buffers(std::string* error);
  [[nodiscard]] bool create_slot(Slot& slot, std::string* error);
  [[nodiscard]] bool ensure_points(Slot& slot, std::size_t point_count, std::string* error);
  [[nodiscard]] bool ensure_device_trace(Slot& slot, std::string* error);
  void update_descriptors(Slot& slot);
  [[nodiscard]] bool check_frame(const EyeFrame& frame, std::string* error) const;
  Slot& slot() { return slots_[slot_]; }
  const Slot& slot() const { return slots_[slot_]; }
  void bind_set(VkCommandBuffer cb) const;
  void stamp(VkCommandBuffer cb, uint32_t query) const;  // a timestamp, when the queue has them

  Context& context_;
  const FramePipelines& pipelines_;
  VkDevice device_ = VK_NULL_HANDLE;
  uint32_t width_px_ = 0, height_px_ = 0;
  std::array<Slot, kFrameSlots> slots_;
  BoundBuffer current_, history_[2], shown_, readback_;
  // Content density's tiles (shader_interface/device_trace.h), one set per eye: each
  // device-traced frame measures them for the next, in queue order.
  BoundBuffer tiles_;
  bool tiles_measured_ = false;              // this frame may read them: the last frame measured them and ended
  bool ended_measuring_ = false;             // the last frame ended (end_frame) having measured them
  const Tables* measured_tables_ = nullptr;  // the tables of the last frame begun
  uint32_t slot_ = 0;       // the slot being recorded
  uint32_t last_slot_ = 0;  // the slot recorded last
  VkDescriptorPool pool_ = VK_NULL_HANDLE;
  int parity_ = 0;  // which of a slot's sets the frame being recorded uses
  bool shown_cleared_ = false;  // the shown image starts opaque black, filled by the first record
  std::unique_ptr<RayCache> ray_cache_;  // made by the first frame with one
  std::uint64_t host_written_ = 0;
  mutable std::uint64_t host_read_ = 0;
};

}  // namespace foveart::gpu
