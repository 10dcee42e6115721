#include "next_chain.hpp"

#include <cstring>

#include <openxr/openxr_reflection.h>

#include "layer/XR_FOVEART_foveated_ray_tracing.h"

namespace foveart::layer {

std::size_t structure_size(std::int32_t type) {
  switch (type) {
#define FOVEART_STRUCT_SIZE(name, type_enum) \
  case static_cast<std::int32_t>(type_enum): \
    return sizeof(name);
    XR_LIST_STRUCTURE_TYPES_CORE(FOVEART_STRUCT_SIZE)
#undef FOVEART_STRUCT_SIZE
    // The extension's own frame structs, which the layer strips from projection layers.
    case static_cast<std::int32_t>(XR_TYPE_FOVEATED_RAY_TRACING_LAYER_FOVEART):
      return sizeof(XrFoveatedRayTracingLayerFOVEART);
    case static_cast<std::int32_t>(XR_TYPE_FOVEATED_DISPLAY_TRANSFORM_FOVEART):
      return sizeof(XrFoveatedDisplayTransformFOVEART);
    default:
      return 0;
  }
}

bool ChainCopies::without(const void* head, const void* remove, const void** out_head) {
  *out_head = head;
  if (head == remove) {
    *out_head = static_cast<const XrBaseInStructure*>(remove)->next;
    return true;
  }
  // Copy every node up to `remove`, then link the last copy past it.
  std::vector<XrBaseInStructure*> copies;
  auto* s = static_cast<const XrBaseInStructure*>(head);
  for (; s != nullptr && s != remove; s = s->next) {
    if (copies.size() >= kMaxChainNodes) return false;
    const std::size_t size = structure_size(type_of(s));
    if (size < sizeof(XrBaseInStructure)) return false;
    auto& storage = nodes_.emplace_back(
        std::make_unique<std::max_align_t[]>((size + sizeof(std::max_align_t) - 1) / sizeof(std::max_align_t)));
    std::memcpy(storage.get(), s, size);
    copies.push_back(reinterpret_cast<XrBaseInStructure*>(storage.get()));
  }
  if (s == nullptr || copies.empty()) return false;  // `remove` is not in the chain
  for (std::size_t i = 0; i + 1 < copies.size(); ++i) copies[i]->next = copies[i + 1];
  copies.back()->next = static_cast<const XrBaseInStructure*>(remove)->next;
  *out_head = copies.front();
  return true;
}

}  // namespace foveart::layer
