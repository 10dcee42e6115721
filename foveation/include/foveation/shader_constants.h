// Constants that the C++ frame (foveation/, layer/) and the GLSL shaders (shaders/)
// share. Both include this one file; it holds nothing but #defines of literals, so it
// reads the same as C, C++ and GLSL. C++ code names them through typed constants next
// to the code that uses them; the shaders through their own short names.
#ifndef FOVEART_SHADER_CONSTANTS_H
#define FOVEART_SHADER_CONSTANTS_H

// Depth as the GPU path carries it: the engine's distance along the ray in metres;
// none returned is FOVEART_DEPTH_UNKNOWN, a miss (the sky) FOVEART_DEPTH_FAR or more.
#define FOVEART_DEPTH_UNKNOWN -1.0
#define FOVEART_DEPTH_FAR 1.0e30

// History reprojection: a history depth within this fraction of the expected one is the
// same surface (else disoccluded).
#define FOVEART_DISOCCLUSION_TOLERANCE 0.1

// Render cache: edge of the cells rays are binned in, in pixels; a kept ray farther than
// a pixel's farthest new ray by more than this fraction lies behind it (occluded); cells
// one workgroup of the prefix sum covers.
#define FOVEART_RAY_CACHE_CELL_PX 2
#define FOVEART_KEPT_RAY_OCCLUSION_TOLERANCE 0.05
#define FOVEART_RAY_CACHE_SCAN_BLOCK 1024u

// Interpolation tables on the device: at most this many chunks per view, each starting
// with a header of FOVEART_CHUNK_HEADER_WORDS words at these offsets.
#define FOVEART_MAX_TABLE_CHUNKS 16
#define FOVEART_CHUNK_FIRST_ROW 0      // first canvas tile row
#define FOVEART_CHUNK_END_ROW 1        // one past the last
#define FOVEART_CHUNK_TILE_INFO 2      // word offset: per tile, first block (rebased) | level << 30
#define FOVEART_CHUNK_BLOCK_PALETTE 3  // word offset: per block + 1, palette offset (rebased)
#define FOVEART_CHUNK_PALETTE 4        // word offset: point indices
#define FOVEART_CHUNK_SLOTS 5          // word offset: 1-byte taps, tile order (rebased ordinal * k)
#define FOVEART_CHUNK_WEIGHTS 6        // word offset: f16 pairs or f32, tile order
#define FOVEART_CHUNK_NEIGHBORS 7      // word offset: 24-bit point indices, row-major canvas pixels (NN)
#define FOVEART_CHUNK_BLOCK_BASE 8     // global index of the chunk's first block
#define FOVEART_CHUNK_PALETTE_BASE 9   // global palette offset of its first entry
#define FOVEART_CHUNK_ORDINAL_BASE 10  // tile-order ordinal of its first pixel
#define FOVEART_CHUNK_PIXEL_BASE 11    // row-major index of its first canvas pixel
#define FOVEART_CHUNK_HEADER_WORDS 16

// Tone-mapping curves of the encode stage (foveation/display_transform.hpp).
#define FOVEART_TONE_MAP_NONE 0u
#define FOVEART_TONE_MAP_PBR_NEUTRAL 1u
#define FOVEART_TONE_MAP_ACES 2u

// The gather's flags (push constant).
#define FOVEART_GATHER_WEIGHTED 1u     // MSM / RBF through the gather layout (else NN)
#define FOVEART_GATHER_F16 2u          // weights stored as IEEE half
#define FOVEART_GATHER_CLAMP_TAPS 4u   // RBF: clamp to the pixel's taps
#define FOVEART_GATHER_CLAMP_BLOCK 8u  // RBF: clamp to the block's valid palette colours
#define FOVEART_GATHER_RBF 16u         // renormalise only with half the weight sum valid

// A device-traced frame's control words (shaders/device_rays.comp): the
// engine's FoveartDeviceRayCount (words 0-7), the resolve's indirect
// dispatch, the visible points; and the status the host reads back after it.
#define FOVEART_DEVICE_RESOLVE_DISPATCH 8u
#define FOVEART_DEVICE_VISIBLE_POINTS 11u
#define FOVEART_DEVICE_CONTROL_WORDS 12u
#define FOVEART_DEVICE_STATUS_INVALID_COMPONENTS 0u
#define FOVEART_DEVICE_STATUS_VISIBLE_POINTS 1u
#define FOVEART_DEVICE_STATUS_WORDS 2u

#endif  // FOVEART_SHADER_CONSTANTS_H
