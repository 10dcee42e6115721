// The ray-tracing backend's layout arithmetic, apart from any device so it can
// be tested everywhere: which triangles go into the BLAS in which order, and
// where the shader binding table's regions and records lie.
// Pure functions; no state, no threads, nothing throws.
#pragma once

#include "scene_data.hpp"

#include <vulkan/vulkan.h>

#include <cstdint>
#include <vector>

namespace foveart::gpu_engine {

// The BLAS's primitives: each triangle of the compute BVH once (its leaves may
// list a triangle several times: spatial splits), the opaque ones first
// (geometry 0), then the alpha-masked ones (geometry 1), each in index order.
struct RtPrimitiveOrder {
  std::vector<uint32_t> prims;   // per BLAS primitive: its index into SceneData::triangles
  uint32_t geometry1_first = 0;  // the number of opaque primitives
};
RtPrimitiveOrder order_rt_primitives(const std::vector<uint32_t>& bvh_prims,
                                     const std::vector<GpuTriangle>& triangles);

// One pipeline's binding table: raygen | miss, shadow miss | hit group. Records
// are shaderGroupHandleSize rounded up to shaderGroupHandleAlignment apart; each
// region starts at a multiple of shaderGroupBaseAlignment (from the table's
// start, which itself must lie at such a multiple).
struct BindingTableLayout {
  VkDeviceSize record_stride_bytes = 0;
  VkDeviceSize raygen_offset_bytes = 0;
  VkDeviceSize miss_offset_bytes = 0;  // two records
  VkDeviceSize hit_offset_bytes = 0;   // one record
  VkDeviceSize table_bytes = 0;
};
BindingTableLayout binding_table_layout(uint32_t handle_bytes, uint32_t handle_alignment, uint32_t base_alignment);

}  // namespace foveart::gpu_engine
