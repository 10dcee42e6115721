// The render cache's interface (shaders/ray_cache.glsl and cache_*.comp;
// gpu/ray_cache.hpp): its push constants, the rays its buffers hold, and the
// constants of its passes.
#ifndef FOVEART_SHADER_INTERFACE_RAY_CACHE_H
#define FOVEART_SHADER_INTERFACE_RAY_CACHE_H

#include "gpu/shader_interface/glsl_cpp.h"

// Cells one workgroup of the prefix sum covers (256 threads x 4).
#define FOVEART_RAY_CACHE_SCAN_BLOCK 1024u
// The per-ray and per-cell passes' workgroup size.
#define FOVEART_RAY_CACHE_GROUP_SIZE 256
// CachePush::filter_kind.
#define FOVEART_RAY_CACHE_FILTER_BOX 0u
#define FOVEART_RAY_CACHE_FILTER_BSPLINE2 1u
// CachePush::scan_phase (cache_scan.comp).
#define FOVEART_SCAN_BLOCKS 0u
#define FOVEART_SCAN_BLOCK_SUMS 1u
#define FOVEART_SCAN_ADD_BLOCK_SUMS 2u

FOVEART_SHADER_INTERFACE_BEGIN

// A kept ray: where it hit (w = 0) or its direction (w = 1: a miss or no
// depth), its colour and its age in frames (w).
struct Anchor {
  vec4 point_m_or_direction;
  vec4 rgb_age;
};
// A new ray as uploaded: where it crossed the screen, its depth (as
// depth.h carries it: < 0 none, >= FOVEART_DEPTH_FAR the sky), its colour.
struct NewRay {
  vec4 sample_px_depth;
  vec4 rgb;
};
// A ray this frame: where it lands, its cell (-1: beyond reach or covered) and its slot there.
struct RayFrame {
  vec2 sample_px;
  int cell;
  uint slot;
};
struct CellRay {
  vec2 sample_px;
  vec2 rg;
  float b;
  float unused;
};

FOVEART_PUSH_CONSTANTS(CachePush) {
  vec4 orientation;  // the eye's, x y z w
  vec4 position_m;   // the eye's, xyz
  vec4 tan_lrud;     // tan(left, right, up, down)
  ivec2 size_px;
  ivec2 cells_xy;
  uint kept;         // rays in anchors_in from earlier frames
  uint added;        // this frame's new rays, after them
  uint filter_kind;  // FOVEART_RAY_CACHE_FILTER_*
  uint max_age;      // frames a ray is kept (0: no limit)
  uint scan_phase;   // FOVEART_SCAN_*
  uint cell_count;
  uint capacity;     // anchors either buffer holds
};

FOVEART_SHADER_INTERFACE_END

#endif  // FOVEART_SHADER_INTERFACE_RAY_CACHE_H
