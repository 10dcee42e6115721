// Progress reporting for long, precomputed work (point sets, tables).
#pragma once

#include <functional>

namespace foveart::foveation {

// Called with a fraction in [0, 1] from the thread doing the work; may be empty.
using ProgressFn = std::function<void(double fraction)>;

}  // namespace foveart::foveation
