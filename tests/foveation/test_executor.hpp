// The executor of the tests that do not test threading themselves:
// two threads, started once per test binary.
#pragma once

#include "foveation/executor.hpp"

namespace foveart::foveation::test {

inline Executor& executor() {
  static Executor two_threads(2);
  return two_threads;
}

}  // namespace foveart::foveation::test
