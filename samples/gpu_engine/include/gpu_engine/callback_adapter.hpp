// The GPU sample engine behind the CPU callback contract (FoveartTraceRaysFn,
// foveation/ray_trace.h): for tools that reconstruct on the CPU (`fovea render
// --engine gpu`) and for comparisons against engine::Tracer.
//
// Each batch is a round trip to the device: its rays are packed into a
// host-visible buffer, GpuTracer::record_trace is recorded and submitted, the
// host waits on a fence and copies the colours back. Timings on this path
// include those transfers and the submit + wait; the layer's device trace
// (PFN_xrFoveatedTraceRaysDeviceFOVEART) keeps rays and colours on the device and
// avoids all of it. This adapter is for offline tools and comparisons, not for
// frames.
//
// Lifetime:  create() makes a Vulkan instance and device of its own (a hardware
//            GPU where there is one, else a CPU implementation such as lavapipe;
//            one compute queue; the ray-tracing extensions of rt_device.hpp
//            where offered, unless options.tracer.backend is compute), a GpuTracer on it, staging buffers (grown as
//            batches need), a command pool and buffer and a fence. Destroying
//            the adapter waits for the device and releases all of it.
// Threads:   trace() and the C callback may be called from any number of
//            threads at once; the batches are serialised with a mutex (one
//            submission in flight at a time).
// Rays:      from origins_m/directions or, when those are null, from view +
//            sample_px (foveation::eye_ray_direction), exactly as engine::Tracer;
//            directions are normalised on the host; a ray with a zero or
//            non-finite direction or a non-finite origin is black with NaN depth,
//            as engine::Tracer gives it.
// Depth:     written to out_depth_m when the batch's size carries it: the primary
//            hit distance, +INFINITY for a miss.
// Counters:  counts() are the GpuTracer's device counters (32-bit on the device,
//            packets always 0).
// Errors:    nothing throws; create() returns null with *error; trace() returns a
//            FoveartResult (FOVEART_RESULT_ERROR_INVALID_ARGUMENT for a batch it
//            cannot read, FOVEART_RESULT_ERROR_ENGINE_FAILURE when the device fails).
#pragma once

#include <gpu_engine/gpu_tracer.hpp>

#include <engine/scene.hpp>
#include <engine/tracer.hpp>

#include <foveation/ray_trace.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace foveart::gpu_engine {

struct CallbackAdapterOptions {
  GpuTracerOptions tracer;
  // Take a CPU implementation (lavapipe) even where a hardware GPU exists.
  bool prefer_cpu = false;
  // Enable VK_LAYER_KHRONOS_validation with synchronization validation when it
  // is installed, with a debug messenger for the instance's life; its error
  // messages are kept (validation_errors()).
  bool validate = false;
};

class CallbackAdapter {
 public:
  // Null and *error when there is no Vulkan device with a compute queue or the
  // tracer cannot be created.
  static std::unique_ptr<CallbackAdapter> create(engine::Scene scene, std::string* error);
  static std::unique_ptr<CallbackAdapter> create(engine::Scene scene, const CallbackAdapterOptions& options,
                                                 std::string* error);
  ~CallbackAdapter();
  CallbackAdapter(const CallbackAdapter&) = delete;
  CallbackAdapter& operator=(const CallbackAdapter&) = delete;

  // Traces one batch on the device (see ray_trace.h); a submit and a wait.
  int32_t trace(const FoveartRayBatch* batch) noexcept;

  const std::string& device_name() const;
  // The tracer's backend: "ray_tracing_pipeline" where the device offers
  // VK_KHR_ray_tracing_pipeline (the adapter then enables it) and
  // options.tracer.backend allows it, else "compute".
  const char* backend_name() const;
  // Why the last batch that failed on the device failed (empty: none has).
  std::string last_error() const;
  bool device_is_cpu() const;   // VK_PHYSICAL_DEVICE_TYPE_CPU (lavapipe)
  // Validation is active: the layer is enabled with synchronization validation
  // and a messenger hears it, so validation_errors() can report.
  bool validated() const;
  // Every validation error heard so far, "<message id name>: <message>".
  std::vector<std::string> validation_errors() const;

  const engine::Scene& scene() const;
  engine::Effects scene_effects() const;
  engine::Effects effects() const;
  engine::RayCounts counts() const;
  void reset_counts();

  struct Impl;

 private:
  explicit CallbackAdapter(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace foveart::gpu_engine

extern "C" {
// A FoveartTraceRaysFn on the GPU sample engine; user_data is a
// foveart::gpu_engine::CallbackAdapter*. Each call is a round trip to the device.
int32_t foveart_gpu_engine_trace_rays(void* user_data, const FoveartRayBatch* batch);
}
