// The device trace's indirect launches of the engine's rays (XrFoveatedDeviceRayCountFOVEART::dispatch64
// and ::traceRays, written by shaders/device_rays.comp; checked on the host by tests/gpu/ray_dispatch_test.cpp).
#ifndef FOVEART_SHADER_INTERFACE_RAY_DISPATCH_H
#define FOVEART_SHADER_INTERFACE_RAY_DISPATCH_H

#include "gpu/shader_interface/glsl_cpp.h"

// Rays per workgroup of the dispatch.
#define FOVEART_RAY_DISPATCH_GROUP 64u
// Vulkan's minimum maxComputeWorkGroupCount, every dimension.
#define FOVEART_RAY_DISPATCH_MAX_GROUPS 65535u
// Rays a device trace makes per view at most (gpu/device_trace.cpp refuses more): 2^31 - 1.
#define FOVEART_DEVICE_MAX_RAYS 0x7FFFFFFFu

// The traceRays launch's rows: at most this wide (within Vulkan's minimum maxComputeWorkGroupCount[0] x
// maxComputeWorkGroupSize[0], 65535 x 128) ...
#define FOVEART_TRACE_RAYS_WIDTH 65536u
// ... and at most this many launches in all (Vulkan's minimum maxRayDispatchInvocationCount, 2^30).
#define FOVEART_TRACE_RAYS_MAX_LAUNCHES 0x40000000u

FOVEART_SHADER_INTERFACE_BEGIN

// The workgroups for `rays` rays at 64 each, in rows of at most 65535: an engine's ray is
// (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * 64 + gl_LocalInvocationIndex,
// none when it is >= the count. Up to 65535 workgroups this is the one row (groups, 1).
FOVEART_FUNCTION void ray_dispatch_groups(uint rays, FOVEART_OUT(uint) groups_x, FOVEART_OUT(uint) rows) {
  const uint groups = rays / FOVEART_RAY_DISPATCH_GROUP + (rays % FOVEART_RAY_DISPATCH_GROUP != 0u ? 1u : 0u);
  groups_x = groups < FOVEART_RAY_DISPATCH_MAX_GROUPS ? groups : FOVEART_RAY_DISPATCH_MAX_GROUPS;
  rows = groups <= FOVEART_RAY_DISPATCH_MAX_GROUPS
             ? 1u
             : groups / FOVEART_RAY_DISPATCH_MAX_GROUPS + (groups % FOVEART_RAY_DISPATCH_MAX_GROUPS != 0u ? 1u : 0u);
}

// The vkCmdTraceRaysIndirectKHR size for `rays` rays: rows of FOVEART_TRACE_RAYS_WIDTH (one row of
// `rays` below that), at most FOVEART_TRACE_RAYS_MAX_LAUNCHES launches. Launch (x, y) traces ray
// y * width + x, then that plus width * height while below the count (only past 2^30 rays).
FOVEART_FUNCTION void trace_rays_size(uint rays, FOVEART_OUT(uint) width, FOVEART_OUT(uint) height) {
  const uint max_rows = FOVEART_TRACE_RAYS_MAX_LAUNCHES / FOVEART_TRACE_RAYS_WIDTH;
  width = rays < FOVEART_TRACE_RAYS_WIDTH ? rays : FOVEART_TRACE_RAYS_WIDTH;
  const uint rows = rays / FOVEART_TRACE_RAYS_WIDTH + (rays % FOVEART_TRACE_RAYS_WIDTH != 0u ? 1u : 0u);
  height = rows < 1u ? 1u : (rows < max_rows ? rows : max_rows);
}

FOVEART_SHADER_INTERFACE_END

#endif  // FOVEART_SHADER_INTERFACE_RAY_DISPATCH_H
