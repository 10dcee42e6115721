// The foveated frame in six stages (docs/design.md, "One frame in stages"),
// one hierarchy for the CPU and the device. Each stage reads what the stages
// before it hand on (the structs below), never their internals, and writes
// into the frame's resources (FrameResources): host images on the CPU
// (HostFrame), the command buffer being recorded and the eye's buffers on the
// device (gpu::DeviceFrame, gpu/device_stages.hpp). A stage set is chosen once
// (make_cpu_stages, gpu::make_device_stages) and FoveatedView runs it in order.
//
//   stage                     CPU (make_cpu_stages)        device (gpu::make_device_stages)
//   1-3. select, rays, trace  CallbackTrace                the engine's device trace and resolve,
//                                                          or CallbackTrace with the colours uploaded
//   4. reconstruct            GatherReconstruction         scatter + gather
//   5. temporal history       NoHistory, ImageHistory,     the image history, or the render cache
//                             RayHistory                   (gpu::RayCache), as the host decides
//   6. encode                 HostEncode (encode_rgba8)    display transform, encode, copy into the image
//
// Stages 1-3 run fused per run of the point set on the CPU (a run's rays go
// to the engine while they are hot). Stage 5 decides its restarts on the host
// for both sides (TemporalHistory::decide); the device's history wraps the
// host's decision and records its application.
//
// Resources: a stage asks the frame for its side once (host() or device(),
// null when the frame is the other side's) and fails with a clear error on a
// mismatch: a virtual accessor, not casts, and not templates, since the layer
// picks a stage set at run time.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "foveation/display_transform.hpp"
#include "foveation/executor.hpp"
#include "foveation/gather.hpp"
#include "foveation/gaze_mapping.hpp"
#include "foveation/image.hpp"
#include "foveation/ray_cache.hpp"
#include "foveation/ray_trace.h"
#include "foveation/temporal_blend.hpp"

namespace foveart::gpu {
struct DeviceFrame;  // gpu/device_stages.hpp
}  // namespace foveart::gpu

namespace foveart::foveation {

struct HostFrame;

// What one frame's stages read and write, on the host or on the device.
class FrameResources {
 public:
  virtual ~FrameResources() = default;
  virtual HostFrame* host() { return nullptr; }
  virtual gpu::DeviceFrame* device() { return nullptr; }
};

// A frame on the host: the reconstruction (stage 4), the image after the
// history (stage 5) and the RGBA8 rows it is encoded into (stage 6).
struct HostFrame final : FrameResources {
  ImageRgb reconstructed;
  const ImageRgb* output = nullptr;  // the history's image, or `reconstructed`; valid until the next frame
  std::uint8_t* rgba8 = nullptr;     // width x height RGBA8 texels (the swapchain's staging); null: not encoded
  bool srgb = true;                  // sRGB-encode (an sRGB swapchain format)
  DisplayTransform display;          // exposure and tone-mapping curve before the encode
  HostFrame* host() override { return this; }
};

// What every stage of one frame knows.
struct FrameContext {
  FoveartEyeView view{};
  GazeMapping mapping;             // the canvas at this frame's foveation centre
  std::uint64_t frame_index = 0;
  std::uint64_t sample_seed = 0;   // this frame's jitter seed
  bool restart = false;            // a saccade's or blink's frame: the history restarts at its onset
  FoveartTraceRaysFn trace_rays = nullptr;  // the engine (CallbackTrace)
  void* user_data = nullptr;
};

// Stages 1-3 hand on: one colour per point, and what the history may need.
struct TracedPoints {
  PointColors colors;                            // a slot per point of the set; a = 1: traced this frame
  std::vector<float> depth_m;                    // per point: nearest hit of its rays (NaN: none returned)
  // Per point: the rays it cast this frame (0: none; not traced, or filled from its parents).
  std::vector<std::uint16_t> rays_cast;
  // The points with a colour this frame, per run of the set: those traced, then those filled
  // (content density), each ascending.
  std::vector<std::vector<std::uint32_t>> runs;
  bool any_depth = false;                        // the engine returned a depth for some point
  // Only for a history that keeps rays (TemporalHistory::keeps_rays):
  std::vector<std::vector<TracedRay>> rays;      // per run: its rays
  // Per point: the farthest hit of its rays (NaN: one gave none; -inf: filled by content density, no ray).
  std::vector<float> farthest_m;
};

// Content-aware density's CPU cost per stage (docs/content_density.md), ms;
// the two per-point stages are their CPU time over the threads, divided by the threads.
struct DensityCost {
  double levels_ms = 0.0;   // the tiles' levels from the last frame's ranges; the first frame's builds the set's levels
  double test_ms = 0.0;     // the per-point test: thinned or traced, and rays by the tile's contrast
  double observe_ms = 0.0;  // the traced points' colours into their tiles' ranges
  double fill_ms = 0.0;     // the thinned points from their parents
  double total_ms() const { return levels_ms + test_ms + observe_ms + fill_ms; }
};

struct TraceStats {
  std::uint32_t points = 0;          // visible points traced
  std::uint32_t points_thinned = 0;  // visible points left untraced in flat tiles, filled from their parents
  std::uint64_t rays = 0;            // primary rays handed to the engine
  std::uint64_t failed_batches = 0;  // the engine returned an error (or threw)
  std::uint64_t invalid_colours = 0; // NaN, infinite or negative colour components
  double select_ms = 0.0;            // per-frame set-up before the fused pass
  double trace_ms = 0.0;             // selection, rays, engine, colour per point
  // Content-aware density's share of select_ms and trace_ms: density.total_ms().
  double density_ms = 0.0;
  DensityCost density;               // ... per stage
  // The frame's resources failed (the wrong side, a device call): not the engine's doing.
  std::string error;
  bool ok() const { return failed_batches == 0 && invalid_colours == 0 && error.empty(); }
};

// Stages 1-3: the visible points' rays through the engine, one colour each.
class TraceStage {
 public:
  virtual ~TraceStage() = default;
  virtual TraceStats trace(const FrameContext& frame, FrameResources& resources, Executor& executor) = 0;
  virtual const TracedPoints& traced() const = 0;
};

// Stage 4: every screen pixel from the traced points.
class ReconstructStage {
 public:
  virtual ~ReconstructStage() = default;
  // false with *error when the resources cannot take it.
  [[nodiscard]] virtual bool reconstruct(const FrameContext& frame, const TracedPoints& traced,
                                         FrameResources& resources, Executor& executor, GatherStats* stats,
                                         std::string* error) = 0;
};

// Stage 5's decision for one frame, and what applying it counted.
struct TemporalFrame {
  bool kept = false;   // a history is kept at all (not NoHistory)
  bool reset = true;   // the output is this frame alone
  std::optional<FoveartEyeView> history_view;  // an image history to reproject from this view
  TemporalOptions blend;    // current_weight: this frame's blend weight
  // RayHistory: the cache forgets every kept ray first, and per screen pixel
  // (row-major) x, the footprint it filters with (1: the pixel filter; wider
  // beyond the pixel grid) and y, the distance beyond which a kept ray landing
  // there is covered (not finite or negative: this frame cannot tell).
  bool rays = false;
  bool ray_restart = false;
  PixelFilter ray_filter = PixelFilter::box;
  std::uint32_t ray_max_age_frames = 0;
  const std::vector<glm::vec2>* ray_pixels = nullptr;  // null after FoveatedView::plan (the device makes them)
  // Applied here (accumulate): pixels of an image history that were off the
  // last view, uncovered, or reprojected through the engine's depth.
  std::uint64_t history_off_screen = 0, history_disoccluded = 0, history_with_depth = 0;
};

// Stage 5: what a frame keeps from earlier frames.
class TemporalHistory {
 public:
  virtual ~TemporalHistory() = default;
  // The trace must keep this frame's rays (TracedPoints::rays, farthest_m).
  virtual bool keeps_rays() const { return false; }
  // After a failed frame: the next one starts a new history.
  virtual void forget() = 0;
  // This frame's decision for a history applied elsewhere (the GPU path); keeps no image.
  virtual TemporalFrame decide(const FrameContext& frame, const TracedPoints& traced, Executor& executor) = 0;
  // Decides and applies the history to this frame's reconstruction in
  // `resources` (on the host: HostFrame::output, valid until the next call);
  // false with *error when the resources cannot take it.
  [[nodiscard]] virtual bool apply(const FrameContext& frame, const TracedPoints& traced, FrameResources& resources,
                                   Executor& executor, TemporalFrame* decision, std::string* error) = 0;
  // RayHistory: the rays kept after the last frame.
  virtual std::size_t kept_rays() const { return 0; }
};

// Stage 6: the frame for a swapchain (display transform, 8-bit encode).
class EncodeStage {
 public:
  virtual ~EncodeStage() = default;
  [[nodiscard]] virtual bool encode(const FrameContext& frame, FrameResources& resources, Executor& executor,
                                    std::string* error) = 0;
};

// The host's resources of a frame, or *error naming the stage that needs them.
HostFrame* host_frame(FrameResources& resources, const char* stage, std::string* error);

// One frame's stages, chosen once; FoveatedView runs them in order.
struct FrameStages {
  std::unique_ptr<TraceStage> trace;              // 1-3
  std::unique_ptr<ReconstructStage> reconstruct;  // 4
  std::unique_ptr<TemporalHistory> history;       // 5
  std::unique_ptr<EncodeStage> encode;            // 6
};

// What a reconstruction elsewhere takes from a frame: stage 3's points and
// stage 5's decision, at the frame's canvas mapping.
struct FrameHandOff {
  const TracedPoints* traced = nullptr;  // no points after FoveatedView::plan (traced on the device)
  std::uint64_t sample_seed = 0;         // the frame's jitter seed (FrameContext::sample_seed)
  TemporalFrame temporal;
  GazeMapping mapping;
  FoveartEyeView view{};
  RbfClamp rbf_clamp = RbfClamp::block;
};

}  // namespace foveart::foveation
