// The render cache's interface (shaders/ray_cache.glsl and cache_*.comp;
// gpu/ray_cache.hpp): the rays its buffers hold and the constants of its
// passes. The push constants: cache_push.h (cache_rays, _scan, _bin, _filter,
// _count), cache_device_rays.h, cache_pixels.h.
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
// CachePush::phase of cache_scan.comp.
#define FOVEART_SCAN_BLOCKS 0u
#define FOVEART_SCAN_BLOCK_SUMS 1u
#define FOVEART_SCAN_ADD_BLOCK_SUMS 2u
// CachePush::phase of cache_count.comp: before the frame's passes, after them.
#define FOVEART_CACHE_COUNT_BEGIN 0u
#define FOVEART_CACHE_COUNT_END 1u
// CachePush::flags.
#define FOVEART_CACHE_RESTART 1u      // forget every kept ray first (the host's restart rule)
#define FOVEART_CACHE_DEVICE_RAYS 2u  // the device trace's rays: their count from its control words, and
                                      // a fault in its status forgets every ray at the frame's end
// The count words (ray_cache.glsl Counts), kept on the device from frame to frame.
#define FOVEART_CACHE_KEPT 0u      // rays kept from earlier frames: anchors_in[0, kept)
#define FOVEART_CACHE_ADDED 1u     // this frame's new rays, after them
#define FOVEART_CACHE_KEPT_OUT 2u  // appended by cache_bin: the next frame's kept rays
#define FOVEART_CACHE_DISPATCH 4u  // x, y, z: cache_rays' and cache_bin's indirect dispatch (16-byte aligned)
#define FOVEART_CACHE_COUNT_WORDS 8u
// The per-pixel passes' encoding of a farthest hit (cache_device_rays,
// cache_pixels): 0 none, 1 + the float's bits for a hit at a finite distance,
// FOVEART_CACHE_FAR_UNKNOWN for a miss or no depth; atomicMax picks the farthest.
#define FOVEART_CACHE_FAR_UNKNOWN 0xFFFFFFFFu

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

FOVEART_SHADER_INTERFACE_END

#endif  // FOVEART_SHADER_INTERFACE_RAY_CACHE_H
