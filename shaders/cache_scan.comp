#version 450
// The render cache, pass 2 (ray_cache.glsl): an exclusive prefix sum of the
// cells' counts, in blocks of 1024: phase 0 scans each block and stores its
// sum, phase 1 (one workgroup) scans the block sums and stores the total at
// [cell_count], phase 2 adds each block's offset to its cells.
#extension GL_GOOGLE_include_directive : require
#include "ray_cache.glsl"

layout(local_size_x = GROUP_SIZE) in;

#define SCAN_ARRAY cells
#define SCAN_THREADS GROUP_SIZE
#include "scan.glsl"

void main() {
  const uint blocks = (cell_count + SCAN_BLOCK - 1u) / SCAN_BLOCK;
  const uint sums = cell_count + 1u;  // where the block sums are
  if (phase == FOVEART_SCAN_BLOCKS) {
    const uint b = gl_WorkGroupID.x;
    if (b >= blocks) return;  // uniform per workgroup
    const uint total = scan_block(0u, b * SCAN_BLOCK, min(SCAN_BLOCK, cell_count - b * SCAN_BLOCK), 0u);
    if (gl_LocalInvocationID.x == 0u) cells[sums + b] = total;
  } else if (phase == FOVEART_SCAN_BLOCK_SUMS) {
    const uint total = scan_all(sums, blocks);
    if (gl_LocalInvocationID.x == 0u) cells[cell_count] = total;
  } else {
    for (uint i = gl_GlobalInvocationID.x; i < cell_count; i += stride()) cells[i] += cells[sums + i / SCAN_BLOCK];
  }
}
