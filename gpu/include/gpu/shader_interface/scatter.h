// shaders/scatter.comp's push constants (gpu/eye_reconstruct.cpp).
#ifndef FOVEART_SHADER_INTERFACE_SCATTER_H
#define FOVEART_SHADER_INTERFACE_SCATTER_H

#include "gpu/shader_interface/glsl_cpp.h"

FOVEART_SHADER_INTERFACE_BEGIN

FOVEART_PUSH_CONSTANTS(ScatterPush) {
  uint count;        // entries in uploaded[]
  uint point_count;  // slots in colors[]
};

FOVEART_SHADER_INTERFACE_END

#endif  // FOVEART_SHADER_INTERFACE_SCATTER_H
