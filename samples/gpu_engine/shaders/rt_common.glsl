// What the ray-tracing pipeline's stages share: the closest-hit payload, and the
// map from a BLAS primitive to the scene's triangle (set 0, binding 1). The BLAS
// holds the traced triangles (those the compute BVH holds) in up to two
// geometries: the opaque ones first, then the alpha-masked ones (non-opaque, so
// the any-hit shader decides per hit). prims[] lists geometry 0's triangles,
// then geometry 1's; GEOMETRY1_FIRST is where geometry 1's start.
#ifndef FOVEART_GPU_RT_COMMON_GLSL
#define FOVEART_GPU_RT_COMMON_GLSL

#extension GL_EXT_ray_tracing : require

struct SceneHit {
  float t;   // hit distance along the ray (gl_HitTEXT)
  float u;   // barycentric weight of p1
  float v;   // barycentric weight of p2
  uint tri;  // index into tris[]
  uint hit;  // 0: a miss
};

layout(constant_id = 2) const uint GEOMETRY1_FIRST = 0u;
layout(std430, set = 0, binding = 1) readonly buffer Prims { uint prims[]; };

uint rt_triangle(int geometry, int primitive) {
  return prims[(geometry != 0 ? GEOMETRY1_FIRST : 0u) + uint(primitive)];
}

#endif
