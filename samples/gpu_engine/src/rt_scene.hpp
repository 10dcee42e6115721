// The scene as acceleration structures for GpuTracer's ray-tracing-pipeline
// backend: one BLAS over the triangles the compute BVH holds (world space, as
// bvh.cpp gives them to Embree), in up to two geometries (the opaque triangles
// first, flagged VK_GEOMETRY_OPAQUE_BIT_KHR; then the alpha-masked ones,
// non-opaque, so rt_alpha.rahit decides per hit), and a TLAS with one instance
// of it (identity transform; no instance when the scene has no triangles).
//
// Lifetime:  create() uploads the vertices through staging, then records the
//            builds into a command buffer of its own,
//            submits it on context.queue and waits for it: the caller must not
//            use that queue from another thread meanwhile. Afterwards only the
//            acceleration structures and their storage are kept; they must
//            outlive every submission that traces against them.
// Errors:    nothing throws; null + *error.
#pragma once

#include <gpu_engine/gpu_tracer.hpp>

#include "rt_functions.hpp"
#include "scene_data.hpp"
#include "vk_buffer.hpp"

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace foveart::gpu_engine {

class RtScene {
 public:
  // The acceleration structures' storage, the build scratch and the vertex
  // input in device-local memory from `ledger` (the vertices through staging).
  static std::unique_ptr<RtScene> create(const GpuContext& context, const RtFunctions& functions,
                                         const std::shared_ptr<MemoryLedger>& ledger, const SceneData& data,
                                         std::string* error);
  ~RtScene();
  RtScene(const RtScene&) = delete;
  RtScene& operator=(const RtScene&) = delete;

  VkAccelerationStructureKHR tlas() const { return tlas_; }
  // Per BLAS primitive, geometry 0's then geometry 1's: its index into
  // SceneData::triangles (set 0, binding 1 of the ray-tracing shaders).
  const std::vector<uint32_t>& prims() const { return prims_; }
  // Where geometry 1's primitives start in prims() (rt_common.glsl's GEOMETRY1_FIRST).
  uint32_t geometry1_first() const { return geometry1_first_; }

 private:
  RtScene() = default;
  [[nodiscard]] bool build(const GpuContext& context, const SceneData& data, std::string* error);
  // The steps of build: the vertices uploaded, then the BLAS and the TLAS recorded.
  struct Build;  // one build's inputs and the buffers that outlive its commands (rt_scene.cpp)
  bool upload_vertices(Build& b, const SceneData& data);
  bool create_structure(Build& b, VkAccelerationStructureTypeKHR type,
                        VkAccelerationStructureBuildGeometryInfoKHR* info, const uint32_t* max_counts,
                        DeviceBuffer* storage, DeviceBuffer* scratch, VkAccelerationStructureKHR* out);
  bool build_blas(Build& b);
  bool build_tlas(Build& b);

  VkDevice device_ = VK_NULL_HANDLE;
  const RtFunctions* fn_ = nullptr;
  std::vector<uint32_t> prims_;
  uint32_t geometry1_first_ = 0;
  std::shared_ptr<MemoryLedger> ledger_;
  DeviceBuffer blas_storage_, tlas_storage_;
  VkAccelerationStructureKHR blas_ = VK_NULL_HANDLE;
  VkAccelerationStructureKHR tlas_ = VK_NULL_HANDLE;
};

}  // namespace foveart::gpu_engine
