// shaders/gather.comp's push constants and flags (gpu/eye_reconstruct.cpp).
#ifndef FOVEART_SHADER_INTERFACE_GATHER_H
#define FOVEART_SHADER_INTERFACE_GATHER_H

#include "gpu/shader_interface/glsl_cpp.h"
#include "gpu/shader_interface/table_chunks.h"

// GatherPush::flags.
#define FOVEART_GATHER_WEIGHTED 1u     // MSM / RBF through the gather layout (else NN)
#define FOVEART_GATHER_F16 2u          // weights stored as IEEE half
#define FOVEART_GATHER_CLAMP_TAPS 4u   // RBF: clamp to the pixel's taps
#define FOVEART_GATHER_CLAMP_BLOCK 8u  // RBF: clamp to the block's valid palette colours
#define FOVEART_GATHER_RBF 16u         // renormalise only with half the weight sum valid

FOVEART_SHADER_INTERFACE_BEGIN

FOVEART_PUSH_CONSTANTS(GatherPush) {
  ivec2 screen_px;
  ivec2 canvas_offset_px;  // canvas pixel of screen pixel (0, 0)
  ivec2 canvas_px;
  ivec2 first_tile;        // canvas tile of workgroup (0, 0)
  int k;                   // taps (weighted methods)
  int neighbor_k;          // neighbour-table entries per pixel (NN)
  uint flags;              // FOVEART_GATHER_*
  uint chunk_count;
  vec4 fallback_rgb;
  uvec4 chunk_first_row[FOVEART_MAX_TABLE_CHUNKS / 4];
};

FOVEART_SHADER_INTERFACE_END

#endif  // FOVEART_SHADER_INTERFACE_GATHER_H
