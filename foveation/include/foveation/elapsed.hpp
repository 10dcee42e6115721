// Milliseconds of wall-clock time since a steady_clock time point: the one
// timer behind every stage time FoveaRT reports.
#pragma once

#include <chrono>

namespace foveart::foveation {

inline double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace foveart::foveation
