// shaders/encode.comp's push constants (gpu/eye_encode.cpp).
#ifndef FOVEART_SHADER_INTERFACE_ENCODE_H
#define FOVEART_SHADER_INTERFACE_ENCODE_H

#include "gpu/shader_interface/glsl_cpp.h"

FOVEART_SHADER_INTERFACE_BEGIN

FOVEART_PUSH_CONSTANTS(EncodePush) {
  ivec2 size_px;
  uint srgb;       // 1: sRGB-encode
  float exposure;
  uint tone_map;   // FOVEART_TONE_MAP_* (foveation/shader_constants.h)
};

FOVEART_SHADER_INTERFACE_END

#endif  // FOVEART_SHADER_INTERFACE_ENCODE_H
