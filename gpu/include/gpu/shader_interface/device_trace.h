// The device trace's interface (shaders/device_rays.comp, device_resolve.comp;
// gpu/device_trace.hpp): the points and rays its buffers hold, the control
// and status words. Each pass's push constants: device_rays.h, device_resolve.h.
#ifndef FOVEART_SHADER_INTERFACE_DEVICE_TRACE_H
#define FOVEART_SHADER_INTERFACE_DEVICE_TRACE_H

#include "gpu/shader_interface/glsl_cpp.h"

// The control words, written by device_rays.comp's SCAN: the engine's
// XrFoveatedDeviceRayCountFOVEART (words 0-7, the layer's public header), the
// resolve's indirect dispatch of a workgroup per FOVEART_DEVICE_RESOLVE_GROUP
// traced points (also the render cache's), the visible points, those traced and
// those thinned, and the fill's indirect dispatch, a workgroup per
// FOVEART_DEVICE_RESOLVE_GROUP thinned points.
#define FOVEART_DEVICE_RAY_COUNT_WORDS 8u
#define FOVEART_DEVICE_RESOLVE_DISPATCH 8u
#define FOVEART_DEVICE_VISIBLE_POINTS 11u
#define FOVEART_DEVICE_TRACED_POINTS 12u
#define FOVEART_DEVICE_THINNED_POINTS 13u
#define FOVEART_DEVICE_FILL_DISPATCH 14u
#define FOVEART_DEVICE_CONTROL_WORDS 17u
// device_resolve.comp's workgroup: its point passes run an invocation per traced
// (or thinned) point, in workgroups of this many.
#define FOVEART_DEVICE_RESOLVE_GROUP 64
// The status the host reads back after the frame.
#define FOVEART_DEVICE_STATUS_INVALID_COMPONENTS 0u
#define FOVEART_DEVICE_STATUS_VISIBLE_POINTS 1u
#define FOVEART_DEVICE_STATUS_TRACED_POINTS 2u
#define FOVEART_DEVICE_STATUS_RAYS 3u
#define FOVEART_DEVICE_STATUS_THINNED_POINTS 4u
#define FOVEART_DEVICE_STATUS_WORDS 5u
// A thinned point's first ray in its DevicePointRays.
#define FOVEART_DEVICE_THINNED 0xFFFFFFFFu
#define FOVEART_DEVICE_NO_PARENT 0xFFFFFFFFu

// Content density's per-eye tile words (device_density.glsl): a header, then four
// regions of FOVEART_DEVICE_TILE_CAPACITY tiles each: the frame's minimum and maximum
// luminance (ordered float bits; min 0xFFFFFFFF: none seen), the contrast the next
// frame reads (float bits) and its level. The capacity is the tiles of the smallest
// tile size, so any tile_px >= FOVEART_DEVICE_MIN_TILE_PX fits.
#define FOVEART_DEVICE_TILES_MEASURED 0u  // 1: the tiles hold a good frame's contrast
#define FOVEART_DEVICE_TILES_X 1u
#define FOVEART_DEVICE_TILES_Y 2u
#define FOVEART_DEVICE_TILES_PX 3u
#define FOVEART_DEVICE_TILES_HEADER_WORDS 4u
#define FOVEART_DEVICE_TILE_MIN 0u
#define FOVEART_DEVICE_TILE_MAX 1u
#define FOVEART_DEVICE_TILE_CONTRAST 2u
#define FOVEART_DEVICE_TILE_LEVEL 3u
#define FOVEART_DEVICE_TILE_REGIONS 4u
#define FOVEART_DEVICE_MIN_TILE_PX 4u
#define FOVEART_DEVICE_FINEST_LEVEL 3u  // foveation::PointLevels::kFinest

FOVEART_SHADER_INTERFACE_BEGIN

// A point of the set: canvas x, y (pixels), disc radius (pixels), and 0 for a Poisson
// point, 1 for a pixel-grid point, 2 for one of the pixel-exact fovea (PointSet::in_exact_fovea).
struct DevicePoint {
  vec4 position_radius_grid;
};
// A point's content-density level and parents (foveation::PointLevels): its
// nearest level-0 points (FOVEART_DEVICE_NO_PARENT: fewer) and their weights.
struct DeviceLevel {
  uvec4 parents_level;  // parent 0, 1, 2, level
  vec4 weights;         // w0, w1, w2, 0
};
// A visible point's rays, at its rank (device_rays.comp WRITE, read by
// device_resolve.comp): the traced points first, in the set's order, then the
// thinned ones (first_ray FOVEART_DEVICE_THINNED, ray_count 0), in the set's order.
struct DevicePointRays {
  uint point;  // its index in the set
  uint first_ray;
  uint ray_count;
};
// A ray, as the engine reads it (XrFoveatedDeviceRayBatchFOVEART): origin
// in metres and the screen x; unit direction and the screen y.
struct DeviceRay {
  vec4 origin_sample_x;
  vec4 direction_sample_y;
};

FOVEART_SHADER_INTERFACE_END

#endif  // FOVEART_SHADER_INTERFACE_DEVICE_TRACE_H
