#version 450
// The render cache, pass 2 (ray_cache.glsl): an exclusive prefix sum of the
// cells' counts, in blocks of 1024: phase 0 scans each block and stores its
// sum, phase 1 (one workgroup) scans the block sums and stores the total at
// [cell_count], phase 2 adds each block's offset to its cells.
#extension GL_GOOGLE_include_directive : require
#include "ray_cache.glsl"

layout(local_size_x = GROUP_SIZE) in;

shared uint partial[GROUP_SIZE];

// Exclusive scan of cells[offset + first, + count) in place (count <= 1024),
// plus `carry`; returns the sum of those cells. Every invocation calls it.
uint scan_block(uint offset, uint first, uint count, uint carry) {
  const uint t = gl_LocalInvocationID.x;
  uint v[4];
  uint sum = 0u;
  for (uint j = 0u; j < 4u; ++j) {
    const uint i = 4u * t + j;
    v[j] = i < count ? cells[offset + first + i] : 0u;
    sum += v[j];
  }
  partial[t] = sum;
  barrier();
  for (uint step = 1u; step < uint(GROUP_SIZE); step <<= 1u) {  // Hillis-Steele, inclusive
    const uint add = t >= step ? partial[t - step] : 0u;
    barrier();
    partial[t] += add;
    barrier();
  }
  uint at = carry + partial[t] - sum;
  for (uint j = 0u; j < 4u; ++j) {
    const uint i = 4u * t + j;
    if (i < count) cells[offset + first + i] = at;
    at += v[j];
  }
  const uint total = partial[GROUP_SIZE - 1];
  barrier();  // partial[] is read above before the next call writes it
  return total;
}

void main() {
  const uint blocks = (cell_count + SCAN_BLOCK - 1u) / SCAN_BLOCK;
  const uint sums = cell_count + 1u;  // where the block sums are
  if (scan_phase == 0u) {
    const uint b = gl_WorkGroupID.x;
    if (b >= blocks) return;  // uniform per workgroup
    const uint total = scan_block(0u, b * SCAN_BLOCK, min(SCAN_BLOCK, cell_count - b * SCAN_BLOCK), 0u);
    if (gl_LocalInvocationID.x == 0u) cells[sums + b] = total;
  } else if (scan_phase == 1u) {
    uint carry = 0u;
    for (uint first = 0u; first < blocks; first += SCAN_BLOCK) {
      carry += scan_block(sums, first, min(SCAN_BLOCK, blocks - first), carry);
    }
    if (gl_LocalInvocationID.x == 0u) cells[cell_count] = carry;
  } else {
    for (uint i = gl_GlobalInvocationID.x; i < cell_count; i += stride()) cells[i] += cells[sums + i / SCAN_BLOCK];
  }
}
