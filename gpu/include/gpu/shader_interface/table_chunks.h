// The table chunks' layout (gpu/table_pack.hpp; shaders/common.glsl reads it).
#ifndef FOVEART_SHADER_INTERFACE_TABLE_CHUNKS_H
#define FOVEART_SHADER_INTERFACE_TABLE_CHUNKS_H

#include "gpu/shader_interface/glsl_cpp.h"

// Interpolation tables on the device (gpu/table_pack.hpp): at most this many
// chunks per view, each starting with a header of FOVEART_CHUNK_HEADER_WORDS
// words at these offsets.
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

#endif  // FOVEART_SHADER_INTERFACE_TABLE_CHUNKS_H
