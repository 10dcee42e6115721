// A unit quaternion (x, y, z, w) rotating a vector: v + 2 q.xyz x (q.xyz x v + w v).
#ifndef FOVEART_QUAT_GLSL
#define FOVEART_QUAT_GLSL

vec3 rotate(vec4 q, vec3 v) { return v + 2.0 * cross(q.xyz, cross(q.xyz, v) + q.w * v); }
vec4 conjugate(vec4 q) { return vec4(-q.xyz, q.w); }

#endif
