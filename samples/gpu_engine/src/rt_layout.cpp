// order_rt_primitives and binding_table_layout (rt_layout.hpp).
#include "rt_layout.hpp"
#include "vk_helpers.hpp"

#include <algorithm>

namespace foveart::gpu_engine {

RtPrimitiveOrder order_rt_primitives(const std::vector<uint32_t>& bvh_prims,
                                     const std::vector<GpuTriangle>& triangles) {
  std::vector<bool> traced(triangles.size(), false);
  for (uint32_t t : bvh_prims)
    if (t < triangles.size()) traced[t] = true;
  RtPrimitiveOrder order;
  for (uint32_t masked = 0; masked < 2; ++masked) {
    if (masked == 1) order.geometry1_first = static_cast<uint32_t>(order.prims.size());
    for (uint32_t t = 0; t < triangles.size(); ++t)
      if (traced[t] && (triangles[t].masked != 0) == (masked == 1)) order.prims.push_back(t);
  }
  return order;
}

BindingTableLayout binding_table_layout(uint32_t handle_bytes, uint32_t handle_alignment, uint32_t base_alignment) {
  const VkDeviceSize base = std::max<uint32_t>(base_alignment, 1);
  BindingTableLayout l;
  l.record_stride_bytes = align_up(handle_bytes, std::max<uint32_t>(handle_alignment, 1));
  l.raygen_offset_bytes = 0;
  l.miss_offset_bytes = align_up(l.raygen_offset_bytes + l.record_stride_bytes, base);
  l.hit_offset_bytes = align_up(l.miss_offset_bytes + 2 * l.record_stride_bytes, base);
  l.table_bytes = l.hit_offset_bytes + l.record_stride_bytes;
  return l;
}

}  // namespace foveart::gpu_engine
