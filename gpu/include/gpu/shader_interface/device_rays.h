// shaders/device_rays.comp's push constants and flags (gpu/device_trace.cpp).
#ifndef FOVEART_SHADER_INTERFACE_DEVICE_RAYS_H
#define FOVEART_SHADER_INTERFACE_DEVICE_RAYS_H

#include "gpu/shader_interface/glsl_cpp.h"
#include "gpu/shader_interface/device_trace.h"

// DeviceRaysPush::flags.
#define FOVEART_DEVICE_RAYS_BSPLINE2 1u  // the bspline2 pixel filter (else box)
#define FOVEART_DEVICE_RAYS_THIN 2u      // content density thins points (full_contrast > 0)
#define FOVEART_DEVICE_RAYS_VARY 4u      // content density varies rays per point (rays_contrast > 0)
#define FOVEART_DEVICE_RAYS_MEASURED 8u  // the eye's tiles may hold the last frame's contrast
// DeviceRaysPush::pass: device_rays.comp's three dispatches, a compaction in the point set's order.
#define FOVEART_DEVICE_RAYS_COUNT 0u  // a workgroup per block of points: how many of them are visible
#define FOVEART_DEVICE_RAYS_SCAN 1u   // one workgroup: where each block's points begin; the counts
#define FOVEART_DEVICE_RAYS_WRITE 2u  // a workgroup per block: each visible point's rays at its rank
// Points per block: the workgroup size of every pass (128: on lavapipe each group's coroutine
// frames, the invocations' state kept across barriers, then stay under 128 KiB).
#define FOVEART_DEVICE_RAYS_BLOCK 128

FOVEART_SHADER_INTERFACE_BEGIN

FOVEART_PUSH_CONSTANTS(DeviceRaysPush) {
  vec4 tan_lrud;         // the frustum: tan of the left, right, up, down angles
  vec4 orientation;      // unit quaternion xyzw, tracking from view
  vec4 position_m;       // xyz
  ivec2 screen_px;
  vec2 canvas_from_screen_px;
  float margin_px;
  uint rays_per_point;
  uint point_count;
  uint flags;            // FOVEART_DEVICE_RAYS_*
  uvec2 seed;            // low, high word
  uint pass;             // FOVEART_DEVICE_RAYS_COUNT, _SCAN, _WRITE
  float full_contrast;   // ContentDensityOptions
  float rays_contrast;
  uint tile_px;
  vec2 canvas_centre_px;           // the gaze in the point set's canvas
  vec4 rays_step_distance_sq_px2;  // foveation::RaysContrastSteps: where rays_contrast doubles (+inf: never)
};

FOVEART_SHADER_INTERFACE_END

#endif  // FOVEART_SHADER_INTERFACE_DEVICE_RAYS_H
