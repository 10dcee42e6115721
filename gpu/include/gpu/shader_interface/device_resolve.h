// shaders/device_resolve.comp's push constants (gpu/device_trace.cpp).
#ifndef FOVEART_SHADER_INTERFACE_DEVICE_RESOLVE_H
#define FOVEART_SHADER_INTERFACE_DEVICE_RESOLVE_H

#include "gpu/shader_interface/glsl_cpp.h"
#include "gpu/shader_interface/device_trace.h"

FOVEART_SHADER_INTERFACE_BEGIN

FOVEART_PUSH_CONSTANTS(DeviceResolvePush) {
  uint rays_per_point;
  uint point_count;
};

FOVEART_SHADER_INTERFACE_END

#endif  // FOVEART_SHADER_INTERFACE_DEVICE_RESOLVE_H
