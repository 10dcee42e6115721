// libFuzzer: the OpenXR next-chain walker that strips the layer's struct.
// Input: a list of (structure type, flag) pairs making a chain of real structs
// of their registry sizes; the opt-in struct is placed where a flag says. The
// walk must find it, the copy must lack it and keep every other node in
// order, and the app's nodes must stay as they were.
#include <cstddef>
#include <cstdint>
#include <algorithm>
#include <cstring>
#include <memory>
#include <vector>

#include "layer/XR_FOVEART_foveated_ray_tracing.h"
#include "next_chain.hpp"

namespace {
constexpr XrStructureType kOptIn = XR_TYPE_FOVEATED_RAY_TRACING_LAYER_FOVEART;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using foveart::layer::ChainCopies;
  constexpr std::size_t kEntry = 5;  // int32 type + one flag byte
  const std::size_t count = std::min<std::size_t>(size / kEntry, 64);
  std::vector<std::unique_ptr<std::max_align_t[]>> storage;
  std::vector<XrBaseInStructure*> nodes;
  const XrBaseInStructure* opt_in = nullptr;
  for (std::size_t i = 0; i < count; ++i) {
    std::int32_t type = 0;
    std::memcpy(&type, data + i * kEntry, 4);
    const bool place_opt_in = (data[i * kEntry + 4] & 1) != 0 && opt_in == nullptr;
    if (place_opt_in) type = kOptIn;
    const std::size_t known = foveart::layer::structure_size(type);
    const std::size_t bytes = std::max({known, sizeof(XrFoveatedRayTracingLayerFOVEART), sizeof(XrBaseInStructure)});
    auto& block = storage.emplace_back(std::make_unique<std::max_align_t[]>(bytes / sizeof(std::max_align_t) + 1));
    std::memset(block.get(), 0xA5, bytes);
    auto* node = reinterpret_cast<XrBaseInStructure*>(block.get());
    std::memcpy(&node->type, &type, sizeof type);  // any 32-bit value, as an app may write
    if (!nodes.empty()) nodes.back()->next = node;
    node->next = nullptr;
    nodes.push_back(node);
    if (place_opt_in) opt_in = node;
  }
  const void* head = nodes.empty() ? nullptr : nodes.front();
  const auto* found = foveart::layer::find_in_chain<XrBaseInStructure>(head, kOptIn);
  // The first opt-in-typed node (a type from the input may equal it before the flagged one).
  if (opt_in != nullptr && found == nullptr) __builtin_trap();
  if (found == nullptr) return 0;
  std::vector<std::vector<std::uint8_t>> before;
  for (auto* n : nodes) {
    const auto* p = reinterpret_cast<const std::uint8_t*>(n);
    before.emplace_back(p, p + sizeof(XrBaseInStructure));
  }
  ChainCopies copies;
  const void* out = nullptr;
  const bool stripped = copies.without(head, found, &out);
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    if (std::memcmp(before[i].data(), nodes[i], sizeof(XrBaseInStructure)) != 0) __builtin_trap();  // app's node written
  }
  if (!stripped) return 0;
  // Same nodes' types in the same order, without the stripped node.
  std::vector<std::int32_t> expected, got;
  for (auto* n : nodes) {
    if (n != found) expected.push_back(foveart::layer::type_of(n));
  }
  std::size_t walked = 0;
  for (auto* s = static_cast<const XrBaseInStructure*>(out); s != nullptr && walked <= nodes.size(); s = s->next) {
    if (s == found) __builtin_trap();
    got.push_back(foveart::layer::type_of(s));
    ++walked;
  }
  if (got != expected) __builtin_trap();
  return 0;
}
