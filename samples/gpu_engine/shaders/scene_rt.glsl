// The ray-tracing pipeline's scene query (VK_KHR_ray_tracing_pipeline): the
// same interface as scene_bvh.glsl, answered by traceRayEXT against the TLAS in
// set 0, binding 0. Closest hit: hit group 0 (rt_hit.rchit, with rt_alpha.rahit
// on alpha-masked geometry), miss shader 0 (rt_miss.rmiss). Occlusion: no
// closest-hit shader, the first accepted hit ends the ray, miss shader 1
// (rt_shadow.rmiss) clears the flag. Hits have t in [0, tfar] (the compute
// query's (0, tfar]; origins are offset by epsilon, so t = 0 does not arise).
// Ray-generation shaders only.
#ifndef FOVEART_GPU_SCENE_RT_GLSL
#define FOVEART_GPU_SCENE_RT_GLSL

#include "rt_common.glsl"

layout(set = 0, binding = 0) uniform accelerationStructureEXT scene_tlas;
layout(location = 0) rayPayloadEXT SceneHit scene_hit;
layout(location = 1) rayPayloadEXT uint scene_shadow_occluded;

// sbtRecordStride 0: both geometries use hit group 0.
bool scene_closest_hit(vec3 o, vec3 d, float tfar, out float t, out float u, out float v, out uint tri) {
  scene_hit = SceneHit(tfar, 0.0, 0.0, 0u, 0u);
  traceRayEXT(scene_tlas, gl_RayFlagsNoneEXT, 0xFF, 0, 0, 0, o, 0.0, d, tfar, 0);
  t = scene_hit.hit != 0u ? scene_hit.t : tfar;
  u = scene_hit.u;
  v = scene_hit.v;
  tri = scene_hit.tri;
  return scene_hit.hit != 0u;
}

bool scene_occluded(vec3 o, vec3 d, float tfar) {
  scene_shadow_occluded = 1u;
  traceRayEXT(scene_tlas, gl_RayFlagsTerminateOnFirstHitEXT | gl_RayFlagsSkipClosestHitShaderEXT, 0xFF, 0, 0, 1, o,
              0.0, d, tfar, 1);
  return scene_shadow_occluded != 0u;
}

#endif
