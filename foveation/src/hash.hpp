// Counter-based hashing for per-point random numbers (no state between calls).
#pragma once

#include <cstdint>

namespace foveart::foveation::detail {

// SplitMix64 finaliser (Steele, Lea & Flood 2014): a bijective 64-bit mixer.
inline std::uint64_t mix64(std::uint64_t z) {
  z += 0x9E3779B97F4A7C15ull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

// Uniform double in [0, 1) from the top 53 bits.
inline double unit_double(std::uint64_t bits) { return double(bits >> 11) * 0x1.0p-53; }

}  // namespace foveart::foveation::detail
