// hello_foveated --mode full: the app renders every pixel of a view itself,
// the baseline the foveated frame is measured against. The chosen engine
// traces `spp` jittered rays per pixel (the full render's points are its
// pixels) with the conventions the layer uses for its own rays: the view from
// the submitted pose and FOV (foveation::make_eye_view), box-filter jitter
// foveation::pixel_jitter(y * W + x, s, seed) with the layer's sample seed and
// no temporal history (the seed does not change from frame to frame). The
// result goes through the layer's display transform (exposure, tone-map curve)
// and sRGB encode (foveation::encode_rgba8) into the app's own swapchain image.
//   cpu engine: engine::render_full on the injected executor; trace_ms is its wall clock.
//   gpu engine: GpuTracer::record_full on the session's device and queue into a
//     device buffer; trace_ms is from GPU timestamps around it. The linear image
//     is then read back, encoded on the CPU with the same functions as the CPU
//     path and uploaded: that round trip is transfer_encode_ms, kept apart.
// Threads: one thread at a time (the app's). Errors: render() throws
// std::runtime_error (run_app reports it); nothing crosses a C callback.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include <foveation/display_transform.hpp>
#include <foveation/executor.hpp>
#include <foveation/ray_trace.h>

#include "xr_app.hpp"

namespace foveart::gpu_engine {
class GpuTracer;
}

namespace foveart::hello {

// The display transform the layer applies for a frame that chains `exposure`
// (0: the config's) and `tone_map` (USE_CONFIG: the config's), with the config's
// defaults standing for "config": the app reads no layer config file.
foveation::DisplayTransform display_for(float exposure, XrFoveatedToneMapFOVEART tone_map);

// What the full render measured, per eye and per frame in order.
struct FullFrameTimes {
  std::vector<float> trace_ms[2];           // the engine's trace (CPU wall clock / GPU timestamps)
  std::vector<float> transfer_encode_ms[2];  // the rest: display encode, copies, waits
};

struct FullFrameEngine {
  // Exactly one of the two.
  FoveartTraceRaysFn trace_rays = nullptr;  // the CPU engine's callback ...
  void* user_data = nullptr;
  gpu_engine::GpuTracer* gpu = nullptr;     // ... or the GPU engine on the session's device
};

// Makes the ViewRenderer of run_app for --mode full. The engine, executor and
// times must outlive it; so must the GpuTracer (it is destroyed first).
std::unique_ptr<ViewRenderer> make_full_frame(const VulkanDevice& device, const FullFrameEngine& engine,
                                              uint32_t spp, const foveation::DisplayTransform& display,
                                              foveation::Executor* executor, FullFrameTimes* times);

}  // namespace foveart::hello
