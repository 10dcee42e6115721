// The GPU engine's BVH depth (samples/gpu_engine/src/bvh.hpp): bvh_inner_levels counts the
// inner nodes on the longest root-to-leaf path, and the traversal's stack, sized to it
// (scene_bvh.glsl's BVH_STACK), holds every node a traversal that hits every box pushes.
#include "bvh.hpp"

#include <engine/default_scene.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <numeric>
#include <string>
#include <vector>

namespace {

using foveart::gpu_engine::BvhData;
using foveart::gpu_engine::bvh_inner_levels;
using foveart::gpu_engine::GpuNode;
using foveart::gpu_engine::kEmptyChild;
using foveart::gpu_engine::kLeafBit;

constexpr uint32_t leaf(uint32_t first, uint32_t count) { return kLeafBit | (count << 27u) | first; }

GpuNode node(uint32_t left, uint32_t right) {
  GpuNode n{};
  n.left = left;
  n.right = right;
  return n;
}

// The longest path by recursion: the reference for the one-pass count.
uint32_t levels_below(const BvhData& bvh, uint32_t index) {
  uint32_t deepest = 0;
  for (const uint32_t child : {bvh.nodes[index].left, bvh.nodes[index].right})
    if ((child & kLeafBit) == 0u) deepest = std::max(deepest, levels_below(bvh, child));
  return deepest + 1;
}

// The shader's traversal (scene_bvh.glsl) with every box hit: the far child pushed
// wherever both children are inner or non-empty, the near one visited; the most it held.
uint32_t most_pushed_hitting_every_box(const BvhData& bvh) {
  std::vector<uint32_t> stack;
  uint32_t most = 0, ref = 0;
  for (;;) {
    if ((ref & kLeafBit) == 0u) {
      const GpuNode& n = bvh.nodes[ref];
      const bool hl = n.left != kEmptyChild, hr = n.right != kEmptyChild;
      if (hl && hr) {
        stack.push_back(n.right);
        most = std::max(most, uint32_t(stack.size()));
        ref = n.left;
        continue;
      }
      if (hl || hr) {
        ref = hl ? n.left : n.right;
        continue;
      }
    }
    if (stack.empty()) break;
    ref = stack.back();
    stack.pop_back();
  }
  return most;
}

TEST(BvhLevels, CountTheInnerNodesOnTheLongestPath) {
  BvhData root_only;
  root_only.nodes = {node(leaf(0, 2), kEmptyChild)};
  EXPECT_EQ(bvh_inner_levels(root_only), 1u);

  // 0 -> (1 -> (2 -> leaves, leaf), leaf): three levels down the left, one on the right.
  BvhData chain;
  chain.nodes = {node(1, leaf(0, 1)), node(2, leaf(1, 1)), node(leaf(2, 1), leaf(3, 1))};
  EXPECT_EQ(bvh_inner_levels(chain), 3u);
  EXPECT_EQ(most_pushed_hitting_every_box(chain), 3u) << "a push at each level: the stack needs all three";

  // The same depth on the right: the count does not follow only the left children.
  BvhData right;
  right.nodes = {node(leaf(0, 1), 1), node(leaf(1, 1), 2), node(leaf(2, 1), leaf(3, 1))};
  EXPECT_EQ(bvh_inner_levels(right), 3u);
}

TEST(BvhLevels, TheDefaultSceneFitsItsStack) {
  const foveart::engine::Scene scene = foveart::engine::make_default_scene();
  std::vector<uint32_t> triangles(scene.mesh.triangles.size());
  std::iota(triangles.begin(), triangles.end(), 0u);
  BvhData bvh;
  std::string error;
  ASSERT_TRUE(foveart::gpu_engine::build_bvh(scene.mesh, triangles, &bvh, &error)) << error;
  const uint32_t levels = bvh_inner_levels(bvh);
  std::printf("default scene: %zu triangles, %zu nodes, %u inner levels\n", triangles.size(), bvh.nodes.size(), levels);
  EXPECT_EQ(levels, levels_below(bvh, 0));
  EXPECT_LE(levels, foveart::gpu_engine::kMaxBvhDepth + 1);
  EXPECT_GT(levels, 4u) << "a tree of one level would not test the bound";
  EXPECT_LE(most_pushed_hitting_every_box(bvh), levels);
}

}  // namespace
