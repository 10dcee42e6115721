// Bindings and constants shared by the reconstruction shaders (docs/gpu.md).
// One descriptor set for every pipeline; the host side is gpu/ (gpu/eye.hpp).
#ifndef FOVEART_COMMON_GLSL
#define FOVEART_COMMON_GLSL
#extension GL_GOOGLE_include_directive : require
#include "foveation/shader_constants.h"
#include "gpu/shader_interface/depth.h"
#include "gpu/shader_interface/device_trace.h"
#include "gpu/shader_interface/table_chunks.h"

// Table chunks: canvas tile rows [first_row, end_row) of the interpolation
// table (or the neighbour table for NN), each <= maxStorageBufferRange bytes.
// A workgroup reads one chunk only (one 8x8 canvas tile), so the index is
// dynamically uniform (shaderStorageBufferArrayDynamicIndexing).
#define MAX_CHUNKS FOVEART_MAX_TABLE_CHUNKS
layout(set = 0, binding = 0, std430) readonly buffer Chunk { uint words[]; } chunks[MAX_CHUNKS];

// Words of every chunk's header (foveation/shader_constants.h).
#define H_FIRST_ROW FOVEART_CHUNK_FIRST_ROW
#define H_END_ROW FOVEART_CHUNK_END_ROW
#define H_TILE_INFO FOVEART_CHUNK_TILE_INFO
#define H_BLOCK_PALETTE FOVEART_CHUNK_BLOCK_PALETTE
#define H_PALETTE FOVEART_CHUNK_PALETTE
#define H_SLOTS FOVEART_CHUNK_SLOTS
#define H_WEIGHTS FOVEART_CHUNK_WEIGHTS
#define H_NEIGHBORS FOVEART_CHUNK_NEIGHBORS
#define H_ORDINAL_BASE FOVEART_CHUNK_ORDINAL_BASE
#define H_PIXEL_BASE FOVEART_CHUNK_PIXEL_BASE

// Colour of every point this frame; a = 1 traced, 0 not (never spread).
layout(set = 0, binding = 1, std430) buffer Colors { vec4 colors[]; };
// Depth (history reprojection) as the shaders carry it: the engine's distance in
// metres along the ray; no depth is DEPTH_UNKNOWN and a miss (the sky) is
// DEPTH_FAR and above: no NaN or infinity reaches a shader (drivers may
// compile isnan/isinf away).
#define DEPTH_UNKNOWN FOVEART_DEPTH_UNKNOWN
#define DEPTH_FAR FOVEART_DEPTH_FAR

// The reconstruction, one vec4 per screen pixel, row-major: rgb and the
// pixel's depth (its nearest traced point's).
layout(set = 0, binding = 2, std430) buffer Current { vec4 current[]; };
// Temporal history in (last frame's output) and out (this frame's output); a =
// the depth of that frame's pixel.
layout(set = 0, binding = 3, std430) readonly buffer HistoryIn { vec4 history_in[]; };
layout(set = 0, binding = 4, std430) buffer HistoryOut { vec4 history_out[]; };
// The frame's traced points: (point index, r, g, b as float bits), then one
// depth per entry (float bits, 4 per uvec4).
layout(set = 0, binding = 5, std430) readonly buffer Upload { uvec4 uploaded[]; };
// The shown image: RGBA8 texels (R in the low byte), row-major, written by
// good frames only and copied into the swapchain image every frame.
layout(set = 0, binding = 6, std430) writeonly buffer Encoded { uint encoded[]; };
// Depth of every point this frame (DEPTH_UNKNOWN when not traced or none returned).
layout(set = 0, binding = 7, std430) buffer PointDepth { float point_depth[]; };
// The frame slot's status (gpu/shader_interface/device_trace.h): zeroed per
// frame, a device trace's invalid colours counted into it by its resolve.
layout(set = 0, binding = 8, std430) readonly buffer FrameStatus { uint frame_status[]; };
// The frame's trace failed (a device trace's NaN, infinite, negative or
// unwritten colours): the frame keeps the history and the shown image as they were.
bool frame_faulted() { return frame_status[FOVEART_DEVICE_STATUS_INVALID_COMPONENTS] != 0u; }

#endif
