// shaders/device_resolve.comp's push constants (gpu/device_trace.cpp).
#ifndef FOVEART_SHADER_INTERFACE_DEVICE_RESOLVE_H
#define FOVEART_SHADER_INTERFACE_DEVICE_RESOLVE_H

#include "gpu/shader_interface/glsl_cpp.h"
#include "gpu/shader_interface/device_trace.h"

// DeviceResolvePush::pass: device_resolve.comp's dispatches.
#define FOVEART_DEVICE_RESOLVE_POINTS 0u    // a traced point each: the mean of its rays (and its tile's luminance range)
#define FOVEART_DEVICE_RESOLVE_FILL 1u      // a thinned point each: its colour from its parents
#define FOVEART_DEVICE_RESOLVE_CONTRAST 2u  // a tile each: its contrast and level for the next frame
// DeviceResolvePush::flags.
#define FOVEART_DEVICE_RESOLVE_OBSERVE 1u  // content density: the traced colours into the tiles' ranges

FOVEART_SHADER_INTERFACE_BEGIN

FOVEART_PUSH_CONSTANTS(DeviceResolvePush) {
  uint pass;   // FOVEART_DEVICE_RESOLVE_*
  uint flags;  // FOVEART_DEVICE_RESOLVE_OBSERVE
  ivec2 screen_px;
  vec2 canvas_from_screen_px;
  uint tile_px;  // ContentDensityOptions
  float exposure;
  float dark_luminance;
  float full_contrast;
};

FOVEART_SHADER_INTERFACE_END

#endif  // FOVEART_SHADER_INTERFACE_DEVICE_RESOLVE_H
