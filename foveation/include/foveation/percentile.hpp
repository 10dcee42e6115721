// Percentiles by nearest rank (Hyndman & Fan 1996, definition 1): the p50, p95
// and p99 that hello_foveated, the frame report and the pacing bench print.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace foveart::foveation {

// The smallest sample with at least p_percent % of the samples at or below it; 0 for none.
template <typename T>
T percentile(std::vector<T> samples, double p_percent) {
  if (samples.empty()) return T(0);
  std::sort(samples.begin(), samples.end());
  const auto rank = static_cast<std::size_t>(std::ceil(p_percent / 100.0 * static_cast<double>(samples.size())));
  return samples[std::min(samples.size() - 1, rank == 0 ? 0 : rank - 1)];
}

}  // namespace foveart::foveation
