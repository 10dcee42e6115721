// Removing one struct from an app's `next` chain without touching the app's
// structs: every node before it is copied (its size known from the OpenXR
// 1.0.20 registry), the copies are relinked around it, and the nodes after it
// are shared with the app's chain.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>
#include <vector>

#include <openxr/openxr.h>

namespace foveart::layer {

// Nodes walked in an app's chain at most: a chain that loops (invalid usage)
// ends the walk instead of hanging the app's thread.
inline constexpr std::size_t kMaxChainNodes = 1024;

// A node's type as the app wrote it. Read as an integer: an app may store any
// 32-bit value there, and loading one outside XrStructureType's range as the
// enum is undefined behaviour (found by tests/fuzz/fuzz_next_chain).
inline std::int32_t type_of(const void* node) {
  std::int32_t type = 0;
  std::memcpy(&type, static_cast<const std::uint8_t*>(node) + offsetof(XrBaseInStructure, type), sizeof type);
  return type;
}

// The first node of `type` in the chain from `next`; null when absent.
template <class T>
const T* find_in_chain(const void* next, XrStructureType type) {
  std::size_t walked = 0;
  for (auto* s = static_cast<const XrBaseInStructure*>(next); s != nullptr && walked < kMaxChainNodes;
       s = s->next, ++walked) {
    if (type_of(s) == static_cast<std::int32_t>(type)) return reinterpret_cast<const T*>(s);
  }
  return nullptr;
}

// The same for output chains (the app's structs the layer fills in).
template <class T>
T* find_in_out_chain(void* next, XrStructureType type) {
  std::size_t walked = 0;
  for (auto* s = static_cast<XrBaseOutStructure*>(next); s != nullptr && walked < kMaxChainNodes;
       s = s->next, ++walked) {
    if (type_of(s) == static_cast<std::int32_t>(type)) return reinterpret_cast<T*>(s);
  }
  return nullptr;
}

// sizeof the struct of this type in the OpenXR 1.0.20 headers; 0 when unknown.
std::size_t structure_size(std::int32_t type);

class ChainCopies {
 public:
  // The head of a chain equal to `head` without the node `remove` (which must
  // be in it). Nodes before `remove` are copies owned by this object (valid
  // while it lives); the app's nodes are never written. Returns false and
  // leaves *out_head = head when a node before `remove` has a type whose size
  // the layer does not know (it cannot be copied), or `remove` lies beyond
  // kMaxChainNodes nodes.
  bool without(const void* head, const void* remove, const void** out_head);

 private:
  std::vector<std::unique_ptr<std::max_align_t[]>> nodes_;
};

}  // namespace foveart::layer
