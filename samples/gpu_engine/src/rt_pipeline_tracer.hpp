// GpuTracer's VK_KHR_ray_tracing_pipeline backend: the scene's acceleration
// structures (RtScene), two ray-tracing pipelines (trace.rgen for the layer's
// device rays, full.rgen for whole images; both with the miss shaders
// rt_miss/rt_shadow and the hit group rt_hit + rt_alpha), their shader binding
// tables, and recording vkCmdTraceRaysKHR. GpuTracer keeps the descriptor sets,
// the scene's storage buffers and the ray counters for both backends.
//
// Lifetime:  create() loads the entry points and builds the acceleration
//            structures (a submission on context.queue, waited for);
//            create_pipelines() once the pipeline layouts exist. The object
//            must outlive every submission it recorded into; the VkDevice must
//            outlive it.
// Threads:   one at a time, as GpuTracer.
// Sync:      record() binds the pipeline and records the launch; the caller
//            binds the descriptor sets and push constants and orders the launch
//            against its own work (stage VK_PIPELINE_STAGE_RAY_TRACING_SHADER_BIT_KHR).
// Errors:    nothing throws; false/null with *error.
#pragma once

#include <gpu_engine/gpu_tracer.hpp>

#include "rt_functions.hpp"
#include "rt_scene.hpp"
#include "scene_data.hpp"
#include "vk_buffer.hpp"

#include <array>
#include <cstdint>
#include <memory>
#include <string>

namespace foveart::gpu_engine {

class RtPipelineTracer {
 public:
  enum class Entry { trace = 0, full = 1 };

  static std::unique_ptr<RtPipelineTracer> create(const GpuContext& context,
                                                  const std::shared_ptr<MemoryLedger>& ledger, const SceneData& data,
                                                  std::string* error);
  ~RtPipelineTracer();
  RtPipelineTracer(const RtPipelineTracer&) = delete;
  RtPipelineTracer& operator=(const RtPipelineTracer&) = delete;

  const RtScene& scene() const { return *scene_; }

  // Both pipelines, specialised like the compute ones (constant 0: effect bits,
  // 1: max_depth; 2: RtScene::geometry1_first; 3: the scene's texture count),
  // each with its binding table.
  [[nodiscard]] bool create_pipelines(VkPipelineLayout trace_layout, VkPipelineLayout full_layout, uint32_t effect_bits,
                        int max_depth, uint32_t texture_count, std::string* error);

  // Binds `entry`'s pipeline and launches width x height rays. False + *error
  // (nothing recorded) when the launch exceeds the device's limits.
  [[nodiscard]] bool record(VkCommandBuffer cb, Entry entry, uint32_t width, uint32_t height, std::string* error) const;
  // Binds `entry`'s pipeline and launches from the VkTraceRaysIndirectCommandKHR at `args`
  // (vkCmdTraceRaysIndirectKHR: GpuContext::trace_rays_indirect).
  [[nodiscard]] bool record_indirect(VkCommandBuffer cb, Entry entry, VkDeviceAddress args, std::string* error) const;

 private:
  struct Table {  // one pipeline's shader binding table
    VkPipeline pipeline = VK_NULL_HANDLE;
    DeviceBuffer buffer;
    VkStridedDeviceAddressRegionKHR raygen{}, miss{}, hit{}, callable{};
  };

  RtPipelineTracer() = default;
  [[nodiscard]] bool create_pipeline(Entry entry, VkPipelineLayout layout, uint32_t effect_bits, int max_depth, std::string* error);
  bool fill_binding_table(Table& table, std::string* error);

  GpuContext ctx_;
  RtFunctions fn_;
  VkPhysicalDeviceRayTracingPipelinePropertiesKHR props_{};
  VkPhysicalDeviceLimits limits_{};
  std::shared_ptr<MemoryLedger> ledger_;
  uint32_t texture_count_ = 0;
  std::unique_ptr<RtScene> scene_;
  std::array<Table, 2> tables_;
};

}  // namespace foveart::gpu_engine
