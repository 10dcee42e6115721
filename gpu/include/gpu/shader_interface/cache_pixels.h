// shaders/cache_pixels.comp's push constants (gpu/ray_cache.cpp).
#ifndef FOVEART_SHADER_INTERFACE_CACHE_PIXELS_H
#define FOVEART_SHADER_INTERFACE_CACHE_PIXELS_H

#include "gpu/shader_interface/glsl_cpp.h"
#include "gpu/shader_interface/device_trace.h"
#include "gpu/shader_interface/ray_cache.h"  // the cache's structs and constants (no push constants)
#include "gpu/shader_interface/table_chunks.h"

FOVEART_SHADER_INTERFACE_BEGIN

// cache_pixels.comp: per screen pixel the footprint and covering distance,
// from the view's tables (read as gather.comp reads them) and this frame's hits.
FOVEART_PUSH_CONSTANTS(CachePixelsPush) {
  ivec2 screen_px;
  ivec2 canvas_offset_px;  // canvas pixel of screen pixel (0, 0)
  ivec2 canvas_px;
  ivec2 first_tile;        // canvas tile of workgroup (0, 0)
  int k;                   // neighbours per pixel: the taps (weighted tables) or the neighbour table's k (NN)
  uint weighted;           // 1: the gather layout's taps, 0: the neighbour table
  uint chunk_count;
  uint filter_kind;        // FOVEART_RAY_CACHE_FILTER_*
  uvec4 chunk_first_row[FOVEART_MAX_TABLE_CHUNKS / 4];
};

FOVEART_SHADER_INTERFACE_END

#endif  // FOVEART_SHADER_INTERFACE_CACHE_PIXELS_H
