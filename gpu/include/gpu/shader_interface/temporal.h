// shaders/temporal.comp's push constants and their values (gpu/eye_temporal.cpp).
#ifndef FOVEART_SHADER_INTERFACE_TEMPORAL_H
#define FOVEART_SHADER_INTERFACE_TEMPORAL_H

#include "gpu/shader_interface/glsl_cpp.h"

// TemporalPush::constraint and ::reproject.
#define FOVEART_HISTORY_MIN_MAX_CLAMP 0u
#define FOVEART_HISTORY_VARIANCE_CLIP 1u
#define FOVEART_REPROJECT_NONE 0u  // the view did not move
#define FOVEART_REPROJECT_BILINEAR 1u
#define FOVEART_REPROJECT_CATMULL_ROM 2u

FOVEART_SHADER_INTERFACE_BEGIN

FOVEART_PUSH_CONSTANTS(TemporalPush) {
  ivec2 size_px;
  float current_weight;   // this frame's blend weight (TemporalAccumulator::frame_weight)
  float variance_gamma;   // box mu +- gamma sigma
  uint constraint;        // FOVEART_HISTORY_*
  uint reset;             // 1: output = current
  float clip_floor;       // the box's least half-width (TemporalOptions::clip_floor)
  uint reproject;         // FOVEART_REPROJECT_*
  vec4 last_from_view_q;  // rotation (x, y, z, w): this view's space -> the last view's
  vec4 last_from_view_t;  // xyz: this eye's position in the last view's space, metres
  vec4 tan_view;          // this view's tan(left, right, up, down)
  vec4 tan_last;          // the last view's
};

FOVEART_SHADER_INTERFACE_END

#endif  // FOVEART_SHADER_INTERFACE_TEMPORAL_H
