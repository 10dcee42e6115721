// The device trace's interface (shaders/device_rays.comp, device_resolve.comp;
// gpu/device_trace.hpp): the points and rays its buffers hold, the control
// and status words. Each pass's push constants: device_rays.h, device_resolve.h.
#ifndef FOVEART_SHADER_INTERFACE_DEVICE_TRACE_H
#define FOVEART_SHADER_INTERFACE_DEVICE_TRACE_H

#include "gpu/shader_interface/glsl_cpp.h"

// The control words: the engine's XrFoveatedDeviceRayCountFOVEART (words 0-7, the
// layer's public header), the resolve's indirect dispatch, the visible points.
#define FOVEART_DEVICE_RAY_COUNT_WORDS 8u
#define FOVEART_DEVICE_RESOLVE_DISPATCH 8u
#define FOVEART_DEVICE_VISIBLE_POINTS 11u
#define FOVEART_DEVICE_CONTROL_WORDS 12u
// The status the host reads back after the frame.
#define FOVEART_DEVICE_STATUS_INVALID_COMPONENTS 0u
#define FOVEART_DEVICE_STATUS_VISIBLE_POINTS 1u
#define FOVEART_DEVICE_STATUS_WORDS 2u

FOVEART_SHADER_INTERFACE_BEGIN

// A point of the set: canvas x, y (pixels), disc radius (pixels), 1 = on the pixel grid.
struct DevicePoint {
  vec4 position_radius_grid;
};
// A ray, as the engine reads it (XrFoveatedDeviceRayBatchFOVEART): origin
// in metres and the screen x; unit direction and the screen y.
struct DeviceRay {
  vec4 origin_sample_x;
  vec4 direction_sample_y;
};

FOVEART_SHADER_INTERFACE_END

#endif  // FOVEART_SHADER_INTERFACE_DEVICE_TRACE_H
