// Process environment and scratch folders for the runtime's tests (no OpenXR here,
// so tests of the runtime's pure parts can use them next to its XR_NO_PROTOTYPES headers).
#pragma once

#include <map>
#include <string>

namespace foveart::sim::test {

// Sets (or, with an empty value, unsets) FOVEART_SIM_* and friends for this process.
void set_env(const std::map<std::string, std::string>& vars);
// Clears every FOVEART_SIM_* variable.
void clear_sim_env();
// A fresh, empty directory under the build tree for one test.
std::string fresh_dir(const std::string& name);

}  // namespace foveart::sim::test
