// One foveated renderer: created for a session by xrCreateFoveatedRendererFOVEART,
// driven at xrEndFrame for every projection layer that chains an
// XrFoveatedRayTracingLayerFOVEART naming it.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include <foveation/display_transform.hpp>
#include <foveation/temporal_mode.hpp>
#include <foveation/view_settings.hpp>

#ifndef XR_USE_GRAPHICS_API_VULKAN
#define XR_USE_GRAPHICS_API_VULKAN
#endif
#include <vulkan/vulkan.h>

#include "layer/XR_FOVEART_foveated_ray_tracing.h"
#include "layer/display_transform_chain.hpp"  // resolve_display: a frame's display transform
#include "log.hpp"
#include "state.hpp"

namespace foveart::layer {

struct RendererSettings {
  FoveartTraceRaysFn trace_rays = nullptr;  // null with a device trace alone
  void* user_data = nullptr;
  // The engine's device trace (XrFoveatedDeviceTraceInfoFOVEART), when chained.
  PFN_xrFoveatedTraceRaysDeviceFOVEART trace_rays_device = nullptr;
  void* device_user_data = nullptr;
  // The app-recorded trace (XrFoveatedAppTraceInfoFOVEART), when chained: the
  // queue families besides the session's that touch its buffers.
  bool app_trace = false;
  std::vector<uint32_t> app_queue_families;
  XrFoveatedInterpolationFOVEART interpolation = XR_FOVEATED_INTERPOLATION_MSM_FOVEART;
  uint32_t k = 5;
  float density_scale = 1.0f;
  std::optional<float> content_contrast;  // LayerConfig::content_contrast; unset: content_contrast_for_path()
  std::optional<float> content_rays;      // LayerConfig::content_rays; unset: content_rays_for()
  // LayerConfig::content_rays_doubling_deg; unset: content_rays_doubling_for().
  std::optional<float> content_rays_doubling_deg;
  uint32_t rays_per_point = 1;
  // LayerConfig::temporal; empty ("auto"): temporal_for_path() picks it by the reconstruction path.
  std::optional<foveation::TemporalMode> temporal;
  XrFoveatedGazeSourceFOVEART gaze_source = XR_FOVEATED_GAZE_SOURCE_PROVIDER_FOVEART;
  std::string gaze_provider_spec = "sim";
  bool gaze_clock_display_time = false;  // LayerConfig::gaze_clock == "display_time"
  uint32_t threads = 0;  // the config's "threads" (0: all cores)
  std::string cache_dir;
  bool wait_for_tables = false;
  std::string reconstruction = "auto";  // "auto" | "gpu" | "cpu" (LayerConfig::reconstruction)
  // LayerConfig::exposure and ::tone_map: a frame's display transform unless it chains its own.
  foveation::DisplayTransform display;
};

// App's create info over the config's defaults: a field that says "use the
// config" (0, NULL, ..._USE_CONFIG_FOVEART: the extension header's "Defaults") takes it.
// Returns false with a message naming the bad field.
[[nodiscard]] bool resolve_settings(const XrFoveatedRendererCreateInfoFOVEART& info, const LayerConfig& config,
                      RendererSettings* out_settings, std::string* error);

// The temporal mode a view runs: the settings' own, else the path's default ("rays" on the
// GPU path, where it meets the flicker goal; "image" on the CPU path, where the render
// cache costs more than twice the image history).
foveation::TemporalMode temporal_for_path(const RendererSettings& settings, bool reconstruct_on_gpu);

// The content contrast that thins a view's points where the settings leave it unset: on the
// GPU path, where on the benchmark set it traces fewer rays with no detection or flicker added
// that the perceptual metric sees, and its passes cost under 1 % of the trace
// (docs/results/content_density/); off on the CPU path, where its per-point test costs about as
// much frame time as the rays it saves (a frame faster on some scenes, slower on others).
inline constexpr float kDeviceContentContrast = 0.1f;
float content_contrast_for_path(const RendererSettings& settings, bool reconstruct_on_gpu);
// The contrast from which a point casts all its rays where the settings leave it unset:
// foveation::default_rays_contrast of the resolved rays per point and density scale, on both
// paths (at the thesis's density the perceptual metric sees nothing it adds on the benchmark
// set, docs/results/content_density/).
float content_rays_for(const RendererSettings& settings);
// The eccentricity over which that contrast doubles where the settings leave it unset, for a view
// of that temporal mode: foveation::default_rays_doubling_ecc_deg, every 30 degrees with the render
// cache, whose flicker it leaves as it was (docs/results/content_density/whole_eye/); off with the
// image history, whose outer rings flicker more where points cast fewer rays.
float content_rays_doubling_for(const RendererSettings& settings, foveation::TemporalMode temporal);

// The extension's temporal enum and foveation's mode, both ways: false for a value that is
// no mode (USE_CONFIG included).
bool temporal_mode_of(XrFoveatedTemporalFOVEART value, foveation::TemporalMode* out);
XrFoveatedTemporalFOVEART xr_temporal(foveation::TemporalMode mode);

// What a renderer refused or worked around, for XrFoveatedRendererInputStatsFOVEART.
// Atomics: the table builder thread counts too.
struct InputCounters {
  std::atomic<uint64_t> cache_files_rejected{0};
  std::atomic<uint64_t> cache_failures{0};
  std::atomic<uint64_t> table_builds_failed{0};
  std::atomic<uint64_t> table_sets_evicted{0};
  std::atomic<uint32_t> table_sets_resident{0};
  std::atomic<uint64_t> gaze_behind_views{0};
  std::atomic<uint64_t> invalid_image_rect_views{0};
  std::atomic<uint64_t> foreign_session_layers{0};
};

// Where the last frame was reconstructed, for XrFoveatedRendererReconstructionStatsFOVEART.
// Written and read under the renderer's frame lock.
struct ReconstructionStats {
  XrFoveatedReconstructionPathFOVEART path = XR_FOVEATED_RECONSTRUCTION_PATH_NONE_FOVEART;
  foveation::TemporalMode temporal = foveation::TemporalMode::off;  // of the last frame reconstructed
  uint32_t gpu_fallbacks = 0;
  float gpu_scatter_ms[2] = {0, 0};
  float gpu_gather_ms[2] = {0, 0};
  float gpu_temporal_ms[2] = {0, 0};
  float gpu_encode_ms[2] = {0, 0};
  bool temporal_reset_last_frame[2] = {false, false};
  uint64_t temporal_resets = 0;
  bool gaze_saccade_last_frame = false;
  bool gaze_blink_last_frame = false;
};

// What choosing the density by content cost the last frame per eye, for
// XrFoveatedRendererDensityStatsFOVEART (the header says which trace fills which).
// Written and read under the renderer's frame lock.
struct DensityStats {
  uint32_t points_thinned[2] = {0, 0};
  float levels_ms[2] = {0, 0}, test_ms[2] = {0, 0}, observe_ms[2] = {0, 0}, fill_ms[2] = {0, 0};  // host
  float gpu_fill_ms[2] = {0, 0}, gpu_contrast_ms[2] = {0, 0};  // the device trace's timestamps
};

// One foveated renderer of a session: its executor ("threads" threads,
// started here, never per frame), its gaze source, the foveation tables per
// (view size, FOV), and per eye the layer's swapchain and the one foveated
// frame (foveation::FoveatedView). Frames and stats readers are serialised.
class FoveatedRenderer {
 public:
  FoveatedRenderer(std::shared_ptr<SessionState> session, RendererSettings settings);
  ~FoveatedRenderer();
  FoveatedRenderer(const FoveatedRenderer&) = delete;
  FoveatedRenderer& operator=(const FoveatedRenderer&) = delete;

  const RendererSettings& settings() const { return settings_; }

  // Ray traces the views of one projection layer. out_views holds a copy of the
  // app's views; the ones produced are rewritten to the layer's swapchains.
  // rect_valid[v] is false for a view whose imageRect lies outside its
  // swapchain: it is left as the app sent it. Returns how many views were
  // rewritten (0 = everything falls back). display: the XrFoveatedDisplayTransformFOVEART
  // chained to the layer's opt-in struct, or null.
  uint32_t render(XrTime display_time, const XrCompositionLayerProjection& layer,
                  XrCompositionLayerProjectionView* out_views, const std::vector<bool>& rect_valid,
                  const XrFoveatedDisplayTransformFOVEART* display);

  // A projection layer of another session named this renderer: counted, logged once.
  void count_foreign_session_layer();

  void stats(XrFoveatedRendererStatsFOVEART* out_stats) const;

  // The app-recorded trace (the extension header): XR_SUCCESS or the header's error.
  XrResult acquire_ray_batch(const XrFoveatedRayBatchAcquireInfoFOVEART& info, XrFoveatedRayBatchFOVEART* out_batch);
  XrResult release_ray_batch(std::uint64_t batch_id);

 private:
  struct Frames;  // the frame path's state (foveated_renderer.cpp)
  void write_density_stats(XrFoveatedRendererDensityStatsFOVEART* out) const;  // under mutex_

  std::shared_ptr<SessionState> session_;
  RendererSettings settings_;
  mutable std::mutex mutex_;  // one frame at a time; stats readers
  InputCounters input_;       // before frames_: its builder thread counts until frames_ is gone
  ReconstructionStats reconstruction_;
  DensityStats density_;
  LogOnce foreign_once_, release_once_;
  std::unique_ptr<Frames> frames_;  // null when the session has no Vulkan: views pass through
  XrFoveatedRendererStatsFOVEART stats_{};
};

}  // namespace foveart::layer
