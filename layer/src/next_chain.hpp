// Removing one struct from an app's `next` chain without touching the app's
// structs: every node before it is copied (its size known from the OpenXR
// 1.0.20 registry), the copies are relinked around it, and the nodes after it
// are shared with the app's chain.
#pragma once

#include <cstddef>
#include <memory>
#include <vector>

#include <openxr/openxr.h>

namespace foveart::layer {

// sizeof the struct of this type in the OpenXR 1.0.20 headers; 0 when unknown.
std::size_t structure_size(XrStructureType type);

class ChainCopies {
 public:
  // The head of a chain equal to `head` without the node `remove` (which must
  // be in it). Nodes before `remove` are copies owned by this object (valid
  // while it lives); the app's nodes are never written. Returns false and
  // leaves *out_head = head when a node before `remove` has a type whose size
  // the layer does not know (it cannot be copied).
  bool without(const void* head, const void* remove, const void** out_head);

 private:
  std::vector<std::unique_ptr<std::max_align_t[]>> nodes_;
};

}  // namespace foveart::layer
