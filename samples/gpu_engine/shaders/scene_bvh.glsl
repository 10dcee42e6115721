// The compute tracer's scene query: the BVH built on the CPU by Embree's
// rtcBuildBVH (bvh.hpp; set 0, bindings 0 and 1) traversed in the shader, with
// the alpha-mask test per candidate hit. Included by trace_core.glsl where
// FOVEART_RT_PIPELINE is not defined; scene_rt.glsl is the same interface on
// VK_KHR_ray_tracing_pipeline:
//   bool scene_closest_hit(o, d, tfar, out t, out u, out v, out tri)
//   bool scene_occluded(o, d, tfar)
// Hits have t in (0, tfar]; u weights p1, v weights p2; tri indexes tris[].
#ifndef FOVEART_GPU_SCENE_BVH_GLSL
#define FOVEART_GPU_SCENE_BVH_GLSL

#include "scene_data.glsl"

const uint LEAF_BIT = 0x80000000u;
const uint EMPTY_CHILD = LEAF_BIT;
// The built tree's inner levels (bvh_inner_levels, bvh.hpp): a node pushed per level at most.
layout(constant_id = 5) const int BVH_STACK = 64;

struct Node {
  vec3 lmin;
  uint left;
  vec3 lmax;
  uint pad0;
  vec3 rmin;
  uint right;
  vec3 rmax;
  uint pad1;
};

layout(std430, set = 0, binding = 0) readonly buffer Nodes { Node nodes[]; };
layout(std430, set = 0, binding = 1) readonly buffer Prims { uint prims[]; };

// Moeller-Trumbore in Embree 3's form (triangle_intersector_moeller.h): hit
// with t in (0, tfar], u weighting p1, v weighting p2.
bool hit_triangle(uint tri, vec3 o, vec3 d, float tfar, out float t, out float u, out float v) {
  const Triangle tr = tris[tri];
  const vec3 e1 = tr.p0 - tr.p1;
  const vec3 e2 = tr.p2 - tr.p0;
  const vec3 ng = glm_cross(e2, e1);
  const vec3 c = tr.p0 - o;
  const vec3 r = glm_cross(c, d);
  const float den = dot(ng, d);
  const float abs_den = abs(den);
  const float sgn = den < 0.0 ? -1.0 : 1.0;
  const float U = dot(r, e2) * sgn;
  const float V = dot(r, e1) * sgn;
  t = 0.0;
  u = 0.0;
  v = 0.0;
  if (den == 0.0 || U < 0.0 || V < 0.0 || U + V > abs_den) return false;
  const float T = dot(ng, c) * sgn;
  if (!(T > 0.0 && T <= abs_den * tfar)) return false;
  const float rcp_den = 1.0 / abs_den;
  t = T * rcp_den;
  u = U * rcp_den;
  v = V * rcp_den;
  return true;
}

// Slab test; tfar widened by 2 ulp-ish so boxes never cut off a hit on their faces.
bool hit_box(vec3 bmin, vec3 bmax, vec3 o, vec3 inv_d, float tmax, out float tnear) {
  const vec3 t0 = (bmin - o) * inv_d;
  const vec3 t1 = (bmax - o) * inv_d;
  const vec3 lo = min(t0, t1);
  const vec3 hi = max(t0, t1);
  tnear = max(max(lo.x, lo.y), max(lo.z, 0.0));
  const float tf = min(min(hi.x, hi.y), min(hi.z, tmax)) * 1.0000003;
  return tnear <= tf;
}

vec3 safe_inverse(vec3 d) {
  const float tiny = 1e-20;
  return 1.0 / vec3(abs(d.x) < tiny ? (d.x < 0.0 ? -tiny : tiny) : d.x,
                    abs(d.y) < tiny ? (d.y < 0.0 ? -tiny : tiny) : d.y,
                    abs(d.z) < tiny ? (d.z < 0.0 ? -tiny : tiny) : d.z);
}

// This invocation's traversal work (COUNT_WORK): nodes visited (inner and leaf), triangles tested.
uint work_nodes = 0u;
uint work_triangles = 0u;

// Closest hit for t in (0, tfar]; any_hit stops at the first (shadow rays).
bool traverse(vec3 o, vec3 d, float tfar, bool any_hit, out float hit_t, out float hit_u, out float hit_v,
              out uint hit_tri) {
  const vec3 inv_d = safe_inverse(d);
  uint stack[BVH_STACK];
  int sp = 0;
  uint ref = 0u;  // the root node
  bool found = false;
  hit_t = tfar;
  hit_u = 0.0;
  hit_v = 0.0;
  hit_tri = 0u;
  for (;;) {
    if (COUNT_WORK != 0u) ++work_nodes;
    if ((ref & LEAF_BIT) != 0u) {
      const uint first = ref & 0x7FFFFFFu;
      const uint count = (ref >> 27u) & 15u;
      if (COUNT_WORK != 0u) work_triangles += count;
      for (uint k = 0u; k < count; ++k) {
        const uint tri = prims[first + k];
        float t, u, v;
        if (!hit_triangle(tri, o, d, hit_t, t, u, v)) continue;
        if (tris[tri].masked != 0u && !alpha_passes(tri, u, v)) continue;
        found = true;
        hit_t = t;
        hit_u = u;
        hit_v = v;
        hit_tri = tri;
        if (any_hit) return true;
      }
    } else {
      const Node n = nodes[ref];
      float tl, tr;
      const bool hl = n.left != EMPTY_CHILD && hit_box(n.lmin, n.lmax, o, inv_d, hit_t, tl);
      const bool hr = n.right != EMPTY_CHILD && hit_box(n.rmin, n.rmax, o, inv_d, hit_t, tr);
      if (hl && hr) {
        const bool left_first = tl <= tr;
        if (sp < BVH_STACK) stack[sp++] = left_first ? n.right : n.left;
        ref = left_first ? n.left : n.right;
        continue;
      }
      if (hl) {
        ref = n.left;
        continue;
      }
      if (hr) {
        ref = n.right;
        continue;
      }
    }
    if (sp == 0) break;
    ref = stack[--sp];
  }
  return found;
}

bool scene_closest_hit(vec3 o, vec3 d, float tfar, out float t, out float u, out float v, out uint tri) {
  return traverse(o, d, tfar, false, t, u, v, tri);
}

bool scene_occluded(vec3 o, vec3 d, float tfar) {
  float t, u, v;
  uint tri;
  return traverse(o, d, tfar, true, t, u, v, tri);
}

#endif
