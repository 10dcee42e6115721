#version 450
// The tests' device engine (gpu_device_trace_test.cpp): each ray's colour is
// its direction and its depth its screen y, as the test's CPU callback answers.
layout(local_size_x = 64) in;
layout(set = 0, binding = 0, std430) readonly buffer Count { uint count; };
layout(set = 0, binding = 1, std430) readonly buffer Rays { vec4 rays[]; };
layout(set = 0, binding = 2, std430) writeonly buffer Colors { vec4 colors[]; };

void main() {
  // Dispatched from the count's dispatch64: rows of at most 65535 workgroups of 64 rays.
  const uint r = (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * 64u + gl_LocalInvocationIndex;
  if (r >= count) return;
  colors[r] = rays[2u * r + 1u];
}
