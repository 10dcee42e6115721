// IEEE 754 binary16 storage for interpolation weights (k = 20 tables would
// exceed 1 GB with float weights). Weights are small numbers of moderate range,
// so subnormal halves are flushed to zero on encoding and the decoder handles
// zero and normal numbers only (a few integer operations, no table, no F16C).
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>

namespace foveart::foveation {

// Round to nearest even; |x| < 2^-14 -> +-0; |x| >= 65520 or NaN -> the largest
// finite half with x's sign (callers never store such weights: the table falls
// back to MSM for them).
inline std::uint16_t float_to_half(float x) {
  std::uint32_t f = 0;
  std::memcpy(&f, &x, 4);
  const std::uint16_t sign = std::uint16_t((f >> 16) & 0x8000u);
  const std::uint32_t abs = f & 0x7FFFFFFFu;
  if (abs < 0x38800000u) return sign;                          // < 2^-14: flush to zero
  if (abs >= 0x477FF000u) return std::uint16_t(sign | 0x7BFFu);  // >= 65520, inf, NaN
  // Rebias exponent (127 -> 15) and round the 13 dropped mantissa bits to nearest even.
  const std::uint32_t rebased = abs - 0x38000000u;
  const std::uint32_t lsb = (rebased >> 13) & 1u;
  const std::uint32_t rounded = (rebased + 0x0FFFu + lsb) >> 13;
  return std::uint16_t(sign | std::uint16_t(rounded));
}

inline float half_to_float(std::uint16_t h) {
  const std::uint32_t mag = h & 0x7FFFu;
  const std::uint32_t bits = (std::uint32_t(h & 0x8000u) << 16) | (mag ? (mag << 13) + 0x38000000u : 0u);
  float f = 0.0f;
  std::memcpy(&f, &bits, 4);
  return f;
}

}  // namespace foveart::foveation
