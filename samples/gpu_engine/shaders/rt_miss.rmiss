#version 460
// Miss shader 0 of the ray-tracing pipeline: the closest-hit query found nothing.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_ray_tracing : require
#include "rt_common.glsl"

layout(location = 0) rayPayloadInEXT SceneHit scene_hit;

void main() { scene_hit.hit = 0u; }
