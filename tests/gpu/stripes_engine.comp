#version 450
// The render cache's flicker test's device engine (device_ray_cache_test.cpp):
// a sky of stripes fixed in the world, each ray's colour from its direction
// alone, 0.5 + 0.4 sin(60 d + phase) per channel (a period of about 10 px in
// the test's view), so that a frame's sparse rays leave detail to flicker;
// its depth the ray's screen y, as direction_engine.comp's.
layout(local_size_x = 64) in;
layout(set = 0, binding = 0, std430) readonly buffer Count { uint count; };
layout(set = 0, binding = 1, std430) readonly buffer Rays { vec4 rays[]; };
layout(set = 0, binding = 2, std430) writeonly buffer Colors { vec4 colors[]; };

void main() {
  const uint r = gl_GlobalInvocationID.x;
  if (r >= count) return;
  const vec4 d = rays[2u * r + 1u];
  colors[r] = vec4(vec3(0.5) + 0.4 * sin(60.0 * d.xyz + vec3(0.0, 2.0, 4.0)), d.w);
}
