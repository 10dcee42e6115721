#version 460
// Miss shader 1 of the ray-tracing pipeline: the occlusion query found nothing.
#extension GL_EXT_ray_tracing : require

layout(location = 1) rayPayloadInEXT uint scene_shadow_occluded;

void main() { scene_shadow_occluded = 0u; }
