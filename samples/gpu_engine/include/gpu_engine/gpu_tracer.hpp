// The sample engine's Whitted tracer on the GPU (Vulkan 1.1): the same scene,
// shading model, effects and ray counts as engine::Tracer, on one of two
// backends chosen at run time (GpuTracerOptions::backend):
//   compute:               a compute shader over a BVH built on the CPU with
//                          Embree's rtcBuildBVH (any Vulkan 1.1 device);
//   ray_tracing_pipeline:  the same shading loop in a ray-generation shader,
//                          the scene queried with traceRayEXT against a BLAS/TLAS
//                          (VK_KHR_ray_tracing_pipeline; rt_device.hpp enables it).
// Both share the shader source (samples/gpu_engine/shaders/trace_core.glsl) but
// for the scene query, and give the same results within float rounding.
//
// Lifetime:  create() builds the BVH, uploads the scene once into device-local
//            memory through staging (submissions on context.queue, waited for;
//            host-visible memory where the device has no device-local memory
//            that fits, memory_fallback() saying so) and creates the pipelines
//            (ray_tracing_pipeline: also builds the acceleration structures on
//            context.queue); the queue must not be used from another thread
//            during create(). The GpuTracer must outlive every submission of a
//            command buffer it recorded into. The VkDevice must outlive it.
// Threads:   one thread at a time (record_trace, record_full, counts, work_counts, reset_counts).
// Sync:      record_* record bind + descriptor set + push + dispatch or trace
//            rays (and a barrier on the tracer's own ray counters between its
//            dispatches); the caller orders them against its own work, at
//            VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT (compute) or
//            VK_PIPELINE_STAGE_RAY_TRACING_SHADER_BIT_KHR (ray_tracing_pipeline) (the layer's device trace
//            inserts its barriers around the call). Descriptor sets are cached
//            per (buffer, offset, size) and rewritten on every call: a range
//            recorded again needs the earlier submission that used it finished
//            (the layer guarantees it for record_trace); several record_* calls
//            in one command buffer must use distinct ranges.
// Counters:  32-bit on the device (no shaderInt64): read after the submissions
//            finished; they wrap after 2^32 rays of one kind between resets
//            (the work counters carry into a second word: 64-bit).
// Errors:    nothing throws; failures return null/false with *error set.
#pragma once

#ifndef XR_USE_GRAPHICS_API_VULKAN
#define XR_USE_GRAPHICS_API_VULKAN
#endif
#include <vulkan/vulkan.h>
#include <openxr/openxr.h>

#include "layer/XR_FOVEART_foveated_ray_tracing.h"

#include <engine/effects.hpp>
#include <engine/scene.hpp>
#include <engine/tracer.hpp>

#include <cstdint>
#include <memory>
#include <string>

namespace foveart::gpu_engine {

// Bytes a tracer holds on the device, by kind (live allocations; staging excluded).
struct MemoryUse {
  uint64_t device_local_bytes = 0;  // DEVICE_LOCAL memory (buffers and images)
  uint64_t host_visible_bytes = 0;  // host-visible memory that is not device-local
  uint64_t texture_bytes = 0;       // of the above, the texture images
};

// What the last device-trace batch chained (record_trace): its rays' footprints, and a
// non-zero count buffer address (XrFoveatedDeviceRayAddressesFOVEART).
struct BatchChain {
  bool footprints = false;
  bool addresses = false;
};

// The compute tracer's BVH traversal work between two resets (GpuTracerOptions::count_work).
struct WorkCounts {
  bool counted = false;         // count_work on the compute backend; else the counts stay 0
  uint64_t bvh_nodes = 0;       // nodes visited, inner and leaf (each traversal starts at the root)
  uint64_t triangle_tests = 0;  // triangles tested in the leaves visited
};

struct GpuContext {
  VkPhysicalDevice physical_device = VK_NULL_HANDLE;
  VkDevice device = VK_NULL_HANDLE;
  uint32_t queue_family_index = 0;
  VkQueue queue = VK_NULL_HANDLE;  // of queue_family_index: the scene's upload (and acceleration structure builds)
  // The device was created with RayTracingDeviceSupport::enable (rt_device.hpp):
  // VK_KHR_ray_tracing_pipeline, VK_KHR_acceleration_structure, their required
  // extensions and features. A VkDevice cannot be asked; its creator says so.
  bool ray_tracing_enabled = false;
  // ... and its rayTracingPipelineTraceRaysIndirect feature (RayTracingDeviceSupport::trace_rays_indirect()).
  bool trace_rays_indirect = false;
};

enum class GpuBackend {
  automatic,             // ray_tracing_pipeline where GpuContext::ray_tracing_enabled, else compute;
                         // compute too when the ray-tracing backend fails to build (backend_fallback())
  compute,               // the compute shader over the CPU-built BVH
  ray_tracing_pipeline,  // VK_KHR_ray_tracing_pipeline; create() fails without it
};
const char* backend_name(GpuBackend backend);  // "automatic", "compute", "ray_tracing_pipeline"

struct GpuTracerOptions {
  int max_depth = 4;                                // secondary bounces per path, 0..kMaxDepth
  engine::Effects allowed = engine::Effects::all();  // effects to simulate at most
  GpuBackend backend = GpuBackend::automatic;
  // false: behave as if the device had no device-local memory (the host-visible
  // fallback, for tests); memory_fallback() says so.
  bool device_local_memory = true;
  // Benchmark only: count the BVH nodes each traversal visits and the triangles
  // it tests (work_counts()), at the cost of a few atomics per workgroup. The
  // compute backend only: a ray-tracing pipeline's traversal is the driver's.
  bool count_work = false;
  // A device-trace ray's footprint picks its primary hit's texture level (record_trace);
  // false: every lookup at level 0 as the CPU engine's, footprints ignored (its equality tests).
  bool texture_lod = true;
  static constexpr int kMaxDepth = 12;              // the most bounces a pipeline is specialised for
};

class GpuTracer {
 public:
  // Null and *error on failure; never throws.
  static std::unique_ptr<GpuTracer> create(const GpuContext& context, engine::Scene scene,
                                           const GpuTracerOptions& options = {}, std::string* error = nullptr);
  ~GpuTracer();
  GpuTracer(const GpuTracer&) = delete;
  GpuTracer& operator=(const GpuTracer&) = delete;

  // The layer's device trace: records into batch.commandBuffer a dispatch
  // indirect from batch.rayCount (compute), or (ray_tracing_pipeline) a
  // vkCmdTraceRaysIndirectKHR of traceRays at the count buffer's address
  // (XrFoveatedDeviceRayAddressesFOVEART, where the batch has addresses and
  // GpuContext::trace_rays_indirect), else a vkCmdTraceRaysKHR of
  // min(rayCapacity, rays, colors) launches of which those past the count
  // return at once. Each ray's primary hit samples textures at the level of
  // detail of its footprint (XrFoveatedDeviceRayFootprintFOVEART; level 0
  // without one, as the CPU engine). false + *error: nothing usable was recorded.
  [[nodiscard]] bool record_trace(const XrFoveatedDeviceRayBatchFOVEART& batch, std::string* error);

  // A full render of `view` like engine::render_full (box-filter jitter
  // pixel_jitter(y * W + x, s, seed), spp rays per pixel, averaged) into `out`
  // at `offset`: W * H vec4 (rgb, w = the first ray's hit distance, +inf a miss).
  // The compute backend compiles the full-render pipeline at the first call.
  [[nodiscard]] bool record_full(VkCommandBuffer cb, const FoveartEyeView& view, uint32_t spp, uint64_t seed, VkBuffer out,
                   VkDeviceSize offset, std::string* error);

  const engine::Scene& scene() const;
  GpuBackend backend() const;  // compute or ray_tracing_pipeline: the one chosen
  const char* backend_name() const { return gpu_engine::backend_name(backend()); }
  // Why an automatic choice fell back to compute after the ray-tracing backend
  // failed to build (empty: it did not).
  const std::string& backend_fallback() const;
  engine::Effects scene_effects() const;  // what the scene calls for
  engine::Effects effects() const;        // what the kernel simulates (scene & allowed)
  engine::RayCounts counts() const;       // device counters (packets stays 0)
  WorkCounts work_counts() const;         // device counters, 64-bit (GpuTracerOptions::count_work)
  BatchChain last_batch_chain() const;    // of the last record_trace call
  // Nodes of the compute tracer's BVH, inner and non-empty leaves (0 with the
  // ray-tracing pipeline): at most what one traversal visits.
  uint64_t bvh_node_count() const;
  void reset_counts();                    // the ray and the work counters
  // Bytes the tracer holds on the device by kind, staging excluded (MemoryUse:
  // device-local, host-visible, of which texture images).
  MemoryUse memory_use() const;
  // One line when (part of) the scene had to live in host-visible memory: no
  // device-local type fits, an allocation failed, or the options said so. Empty
  // otherwise; the caller logs it once (as backend_fallback()).
  const std::string& memory_fallback() const;

  struct Impl;

 private:
  explicit GpuTracer(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace foveart::gpu_engine

extern "C" {
// The PFN_xrFoveatedTraceRaysDeviceFOVEART of the GPU sample engine; user_data is a
// foveart::gpu_engine::GpuTracer*. XR_ERROR_VALIDATION_FAILURE on bad input,
// XR_ERROR_RUNTIME_FAILURE when recording fails; never throws.
XrResult foveart_gpu_engine_trace_rays_device(void* user_data, const XrFoveatedDeviceRayBatchFOVEART* batch);
}
