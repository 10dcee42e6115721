// The BVH build: Embree's rtcBuildBVH with our node callbacks (Embree 3 API,
// "rtcBuildBVH"; as in Embree's bvh_builder tutorial), then flattened into GpuNode.
#include "bvh.hpp"

#include <embree3/rtcore.h>
#include <glm/common.hpp>

#include <algorithm>
#include <array>
#include <cstring>
#include <limits>
#include <new>

namespace foveart::gpu_engine {
namespace {

// Nodes of the tree Embree builds, allocated with rtcThreadLocalAlloc (freed with the RTCBVH).
struct BuildNode {
  bool leaf = false;
};
struct InnerNode : BuildNode {
  std::array<BuildNode*, 2> child{};
  std::array<RTCBounds, 2> bounds{};
};
struct LeafNode : BuildNode {
  uint32_t count = 0;
  std::array<uint32_t, kMaxLeafSize> prim{};
};

struct BuildContext {
  const engine::Mesh* mesh = nullptr;
};

// RTCCreateNodeFunction: an inner node of two children.
void* create_node(RTCThreadLocalAllocator alloc, unsigned int child_count, void*) {
  if (child_count != 2) return nullptr;
  void* p = rtcThreadLocalAlloc(alloc, sizeof(InnerNode), alignof(InnerNode));
  return p ? new (p) InnerNode() : nullptr;
}

// RTCSetNodeChildrenFunction.
void set_children(void* node, void** children, unsigned int child_count, void*) {
  auto* n = static_cast<InnerNode*>(node);
  for (unsigned int i = 0; i < child_count && i < 2; ++i) n->child[i] = static_cast<BuildNode*>(children[i]);
}

// RTCSetNodeBoundsFunction.
void set_bounds(void* node, const RTCBounds** bounds, unsigned int child_count, void*) {
  auto* n = static_cast<InnerNode*>(node);
  for (unsigned int i = 0; i < child_count && i < 2; ++i) n->bounds[i] = *bounds[i];
}

// RTCCreateLeafFunction: a leaf of at most kMaxLeafSize triangles.
void* create_leaf(RTCThreadLocalAllocator alloc, const RTCBuildPrimitive* prims, size_t count, void*) {
  if (count > kMaxLeafSize) return nullptr;
  void* p = rtcThreadLocalAlloc(alloc, sizeof(LeafNode), alignof(LeafNode));
  if (!p) return nullptr;
  auto* leaf = new (p) LeafNode();
  leaf->leaf = true;
  leaf->count = static_cast<uint32_t>(count);
  for (size_t i = 0; i < count; ++i) leaf->prim[i] = prims[i].primID;
  return leaf;
}

float& lower(RTCBounds& b, unsigned int d) { return d == 0 ? b.lower_x : (d == 1 ? b.lower_y : b.lower_z); }
float& upper(RTCBounds& b, unsigned int d) { return d == 0 ? b.upper_x : (d == 1 ? b.upper_y : b.upper_z); }

void extend(RTCBounds& b, const glm::vec3& p) {
  b.lower_x = std::min(b.lower_x, p.x);
  b.lower_y = std::min(b.lower_y, p.y);
  b.lower_z = std::min(b.lower_z, p.z);
  b.upper_x = std::max(b.upper_x, p.x);
  b.upper_y = std::max(b.upper_y, p.y);
  b.upper_z = std::max(b.upper_z, p.z);
}

RTCBounds empty_bounds() {
  constexpr float inf = std::numeric_limits<float>::infinity();
  RTCBounds b{};
  b.lower_x = b.lower_y = b.lower_z = inf;
  b.upper_x = b.upper_y = b.upper_z = -inf;
  return b;
}

RTCBounds clip_to(const RTCBounds& a, const RTCBuildPrimitive& p) {
  RTCBounds b = a;
  b.lower_x = std::max(b.lower_x, p.lower_x);
  b.lower_y = std::max(b.lower_y, p.lower_y);
  b.lower_z = std::max(b.lower_z, p.lower_z);
  b.upper_x = std::min(b.upper_x, p.upper_x);
  b.upper_y = std::min(b.upper_y, p.upper_y);
  b.upper_z = std::min(b.upper_z, p.upper_z);
  return b;
}

// RTCSplitPrimitiveFunction for spatial splits: the triangle clipped at the
// plane, each side's box within the (possibly already split) primitive's box.
void split_primitive(const RTCBuildPrimitive* prim, unsigned int dim, float pos, RTCBounds* left, RTCBounds* right,
                     void* user) {
  const auto* ctx = static_cast<const BuildContext*>(user);
  const glm::uvec3 t = ctx->mesh->triangles[prim->primID];
  const glm::vec3 v[3] = {ctx->mesh->positions[t.x], ctx->mesh->positions[t.y], ctx->mesh->positions[t.z]};
  RTCBounds l = empty_bounds(), r = empty_bounds();
  for (int i = 0; i < 3; ++i) {
    const glm::vec3 a = v[i], b = v[(i + 1) % 3];
    if (a[static_cast<int>(dim)] <= pos) extend(l, a);
    if (a[static_cast<int>(dim)] >= pos) extend(r, a);
    const float da = a[static_cast<int>(dim)] - pos, db = b[static_cast<int>(dim)] - pos;
    if ((da < 0.0f && db > 0.0f) || (da > 0.0f && db < 0.0f)) {
      glm::vec3 c = a + (da / (da - db)) * (b - a);
      c[static_cast<int>(dim)] = pos;
      extend(l, c);
      extend(r, c);
    }
  }
  *left = clip_to(l, *prim);
  *right = clip_to(r, *prim);
  upper(*left, dim) = std::min(upper(*left, dim), pos);
  lower(*right, dim) = std::max(lower(*right, dim), pos);
}

void set_box(float (&mn)[3], float (&mx)[3], const RTCBounds& b) {
  mn[0] = b.lower_x;
  mn[1] = b.lower_y;
  mn[2] = b.lower_z;
  mx[0] = b.upper_x;
  mx[1] = b.upper_y;
  mx[2] = b.upper_z;
}

// Depth-first flattening; returns the child reference of `n`.
uint32_t flatten(const BuildNode* n, BvhData* out, bool* ok) {
  if (n == nullptr) {
    *ok = false;
    return kEmptyChild;
  }
  if (n->leaf) {
    const auto* leaf = static_cast<const LeafNode*>(n);
    const auto first = static_cast<uint32_t>(out->prims.size());
    if (first >= (1u << 27) || leaf->count == 0) {
      *ok = leaf->count == 0 && *ok;
      return kEmptyChild;
    }
    out->prims.insert(out->prims.end(), leaf->prim.begin(), leaf->prim.begin() + leaf->count);
    return kLeafBit | (leaf->count << 27) | first;
  }
  const auto* inner = static_cast<const InnerNode*>(n);
  const auto index = static_cast<uint32_t>(out->nodes.size());
  out->nodes.emplace_back();
  set_box(out->nodes[index].lmin, out->nodes[index].lmax, inner->bounds[0]);
  set_box(out->nodes[index].rmin, out->nodes[index].rmax, inner->bounds[1]);
  const uint32_t l = flatten(inner->child[0], out, ok);
  const uint32_t r = flatten(inner->child[1], out, ok);
  out->nodes[index].left = l;
  out->nodes[index].right = r;
  return index;
}

GpuNode empty_node() {
  GpuNode n{};
  const RTCBounds e = empty_bounds();
  set_box(n.lmin, n.lmax, e);
  set_box(n.rmin, n.rmax, e);
  n.left = n.right = kEmptyChild;
  return n;
}

}  // namespace

// rtcNewDevice -> rtcNewBVH -> rtcBuildBVH -> flatten -> release (Embree 3 API).
bool build_bvh(const engine::Mesh& mesh, const std::vector<uint32_t>& triangles, BvhData* out, std::string* error) {
  out->nodes.clear();
  out->prims.clear();
  if (triangles.empty()) {
    out->nodes.push_back(empty_node());
    return true;
  }
  std::vector<RTCBuildPrimitive> prims;
  prims.reserve(2 * triangles.size());  // spatial splits add primitives up to the capacity
  RTCBounds all = empty_bounds();
  for (uint32_t tri : triangles) {
    const glm::uvec3 t = mesh.triangles[tri];
    const glm::vec3 a = mesh.positions[t.x], b = mesh.positions[t.y], c = mesh.positions[t.z];
    const glm::vec3 lo = glm::min(a, glm::min(b, c)), hi = glm::max(a, glm::max(b, c));
    RTCBuildPrimitive p{};
    p.lower_x = lo.x;
    p.lower_y = lo.y;
    p.lower_z = lo.z;
    p.upper_x = hi.x;
    p.upper_y = hi.y;
    p.upper_z = hi.z;
    p.geomID = 0;
    p.primID = tri;
    prims.push_back(p);
    extend(all, lo);
    extend(all, hi);
  }
  const size_t count = prims.size();
  prims.resize(prims.capacity());

  RTCDevice device = rtcNewDevice(nullptr);
  if (!device) {
    if (error) *error = "gpu_engine: Embree device creation failed";
    return false;
  }
  RTCBVH bvh = rtcNewBVH(device);
  BuildContext ctx{&mesh};
  RTCBuildArguments args = rtcDefaultBuildArguments();
  args.buildQuality = RTC_BUILD_QUALITY_HIGH;
  args.maxBranchingFactor = 2;
  args.maxDepth = kMaxBvhDepth;
  args.minLeafSize = 1;
  args.maxLeafSize = kMaxLeafSize;
  args.bvh = bvh;
  args.primitives = prims.data();
  args.primitiveCount = count;
  args.primitiveArrayCapacity = prims.size();
  args.createNode = create_node;
  args.setNodeChildren = set_children;
  args.setNodeBounds = set_bounds;
  args.createLeaf = create_leaf;
  args.splitPrimitive = split_primitive;
  args.userPtr = &ctx;
  const auto* root = static_cast<const BuildNode*>(rtcBuildBVH(&args));
  bool ok = root != nullptr && rtcGetDeviceError(device) == RTC_ERROR_NONE;
  if (ok) {
    if (root->leaf) {  // a single leaf: the root node holds it on its left
      out->nodes.push_back(empty_node());
      set_box(out->nodes[0].lmin, out->nodes[0].lmax, all);
      out->nodes[0].left = flatten(root, out, &ok);
    } else {
      flatten(root, out, &ok);
    }
  }
  rtcReleaseBVH(bvh);  // frees every node the callbacks allocated
  rtcReleaseDevice(device);
  if (!ok) {
    out->nodes.clear();
    out->prims.clear();
    if (error) *error = "gpu_engine: rtcBuildBVH failed (" + std::to_string(count) + " triangles)";
    return false;
  }
  return true;
}

uint32_t bvh_inner_levels(const BvhData& bvh) {
  // flatten numbers a node before its children: from the last node back, each
  // node's children are done when it is reached.
  std::vector<uint32_t> levels(bvh.nodes.size(), 1);
  for (size_t i = bvh.nodes.size(); i-- > 0;) {
    for (const uint32_t child : {bvh.nodes[i].left, bvh.nodes[i].right})
      if ((child & kLeafBit) == 0u && child < levels.size()) levels[i] = std::max(levels[i], levels[child] + 1);
  }
  return levels.empty() ? 1u : levels[0];
}

}  // namespace foveart::gpu_engine
