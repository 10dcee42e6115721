// The one exclusive prefix sum of the shaders, for one workgroup of
// SCAN_THREADS invocations, 4 values each (Hillis-Steele over the threads'
// sums): the render cache's cells (cache_scan.comp) and the device trace's
// ray compaction (device_rays.comp). Before including it, define SCAN_ARRAY
// (a uint array of a buffer, scanned in place) and SCAN_THREADS (the local size).
#ifndef FOVEART_SCAN_GLSL
#define FOVEART_SCAN_GLSL

shared uint scan_partial[SCAN_THREADS];

// Exclusive scan of SCAN_ARRAY[offset + first, + count) in place (count <= 4 x SCAN_THREADS),
// plus `carry`; returns the sum of those cells. Every invocation calls it.
uint scan_block(uint offset, uint first, uint count, uint carry) {
  const uint t = gl_LocalInvocationID.x;
  uint v[4];
  uint sum = 0u;
  for (uint j = 0u; j < 4u; ++j) {
    const uint i = 4u * t + j;
    v[j] = i < count ? SCAN_ARRAY[offset + first + i] : 0u;
    sum += v[j];
  }
  scan_partial[t] = sum;
  barrier();
  for (uint step = 1u; step < uint(SCAN_THREADS); step <<= 1u) {  // Hillis-Steele, inclusive
    const uint add = t >= step ? scan_partial[t - step] : 0u;
    barrier();
    scan_partial[t] += add;
    barrier();
  }
  uint at = carry + scan_partial[t] - sum;
  for (uint j = 0u; j < 4u; ++j) {
    const uint i = 4u * t + j;
    if (i < count) SCAN_ARRAY[offset + first + i] = at;
    at += v[j];
  }
  const uint total = scan_partial[SCAN_THREADS - 1];
  barrier();  // scan_partial[] is read above before the next call writes it
  return total;
}

// Exclusive scan of SCAN_ARRAY[offset, + count) in place, any count, by one
// workgroup; returns the total. Every invocation calls it.
uint scan_all(uint offset, uint count) {
  uint carry = 0u;
  for (uint first = 0u; first < count; first += 4u * uint(SCAN_THREADS)) {
    carry += scan_block(offset, first, min(4u * uint(SCAN_THREADS), count - first), carry);
  }
  return carry;
}

#endif
