// A binary BVH in the shader's std430 layout, built on the CPU by Embree's
// rtcBuildBVH (Embree 3 API, RTC_BUILD_QUALITY_HIGH with spatial splits).
#pragma once

#include <engine/scene.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace foveart::gpu_engine {

// A child reference: an inner node index, or (kLeafBit set) a leaf of
// `count` (1..15, bits 27..30) entries of BvhData::prims from `first` (bits 0..26).
inline constexpr uint32_t kLeafBit = 0x80000000u;
inline constexpr uint32_t kEmptyChild = kLeafBit;  // a leaf of zero entries
inline constexpr uint32_t kMaxLeafSize = 4;
inline constexpr uint32_t kMaxBvhDepth = 60;  // Embree's build limit; the shader's stack fits the built tree

// Two child boxes per node (std430: vec3 + uint packs into 16 bytes).
struct GpuNode {
  float lmin[3];
  uint32_t left;
  float lmax[3];
  uint32_t pad0;
  float rmin[3];
  uint32_t right;
  float rmax[3];
  uint32_t pad1;
};
static_assert(sizeof(GpuNode) == 64);

struct BvhData {
  std::vector<GpuNode> nodes;  // nodes[0] is the root (always present); children follow their parent
  std::vector<uint32_t> prims; // leaf entries: indices into Scene::mesh.triangles
};

// The most inner nodes on a path from the root to a leaf (1: the root alone). The
// traversal pushes at most one node per inner level it passes, so its stack needs
// this many entries (scene_bvh.glsl's BVH_STACK).
uint32_t bvh_inner_levels(const BvhData& bvh);

// BVH over the triangles listed in `triangles` (indices into mesh.triangles).
// False + *error when Embree fails.
[[nodiscard]] bool build_bvh(const engine::Mesh& mesh, const std::vector<uint32_t>& triangles, BvhData* out, std::string* error);

}  // namespace foveart::gpu_engine
