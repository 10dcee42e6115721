#version 460
// The closest hit of the ray-tracing pipeline: what scene_closest_hit returns.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_ray_tracing : require
#include "rt_common.glsl"

layout(location = 0) rayPayloadInEXT SceneHit scene_hit;
hitAttributeEXT vec2 barycentrics;  // weights of p1 and p2, as Embree's u and v

void main() {
  scene_hit = SceneHit(gl_HitTEXT, barycentrics.x, barycentrics.y, rt_triangle(gl_GeometryIndexEXT, gl_PrimitiveID),
                       1u);
}
