#version 450
// The layer's device trace on the compute tracer: 64 rays per workgroup,
// dispatched indirectly from XrFoveatedDeviceRayCountFOVEART::dispatch64 (batch_trace.glsl) in rows
// of at most 65535 workgroups.
#extension GL_GOOGLE_include_directive : require
#include "trace_core.glsl"
#include "batch_trace.glsl"

layout(local_size_x = 64) in;

void main() {
  begin_counting();
  trace_batch_ray((gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * 64u + gl_LocalInvocationIndex);
  end_counting();
}
