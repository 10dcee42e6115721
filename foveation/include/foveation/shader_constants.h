// Constants that the CPU frame (foveation/) and the GLSL shaders (shaders/) share: the
// rules both paths follow. Both include this one file; it holds nothing but #defines of
// literals, so it reads the same as C, C++ and GLSL. What only the device frame and its
// shaders share (push constants, buffer structs, flags) is in gpu/shader_interface/.
#ifndef FOVEART_SHADER_CONSTANTS_H
#define FOVEART_SHADER_CONSTANTS_H

// History reprojection: a history depth within this fraction of the expected one is the
// same surface (else disoccluded).
#define FOVEART_DISOCCLUSION_TOLERANCE 0.1

// Render cache: edge of the cells rays are binned in, in pixels; a kept ray farther than
// a pixel's farthest new ray by more than this fraction lies behind it (occluded).
#define FOVEART_RAY_CACHE_CELL_PX 2
#define FOVEART_KEPT_RAY_OCCLUSION_TOLERANCE 0.05

// Tone-mapping curves of the encode stage (foveation/display_transform.hpp).
#define FOVEART_TONE_MAP_NONE 0u
#define FOVEART_TONE_MAP_PBR_NEUTRAL 1u
#define FOVEART_TONE_MAP_ACES 2u

#endif  // FOVEART_SHADER_CONSTANTS_H
