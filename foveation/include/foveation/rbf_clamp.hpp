// De-ringing of RBF results (gather.hpp's RbfClamp): an interpolated value may
// not leave the range of the values it was interpolated from. RBF weights can
// be negative, so without it a step overshoots by up to ~0.6 of its height;
// NN and MSM weights are convex and never leave that range anyway.
//
// One scalar implementation for every caller that clamps one value at a time:
// the gather's pixels with an invalid tap (per channel, over the valid taps)
// and `fovea interpolate` (per query, over its k taps). The gather's SIMD
// kernels do the same min/max lane-wise.
#pragma once

#include <algorithm>
#include <limits>
#include <span>

namespace foveart::foveation {

// The range of the values seen so far; empty (lo = +inf, hi = -inf) at first.
template <typename T>
struct RbfClampRange {
  T lo = std::numeric_limits<T>::infinity();
  T hi = -std::numeric_limits<T>::infinity();

  void include(T value) {
    lo = std::min(lo, value);
    hi = std::max(hi, value);
  }
  bool empty() const { return !(lo <= hi); }
  // Max then min, in the order of the gather kernels (maxps, then minps).
  // Requires a non-empty range.
  T clamp(T value) const { return std::min(std::max(value, lo), hi); }
};

// `value` clamped to the range of `taps` (RbfClamp::taps for one value);
// `value` unchanged when `taps` is empty.
template <typename T>
T rbf_clamp_to_taps(T value, std::span<const T> taps) {
  if (taps.empty()) return value;
  RbfClampRange<T> range;
  for (const T t : taps) range.include(t);
  return range.clamp(value);
}

}  // namespace foveart::foveation
