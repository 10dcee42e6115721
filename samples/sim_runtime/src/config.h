// Runtime configuration read from the environment (sim_runtime/sim_env.h).
#pragma once

#include <cstdint>
#include <optional>
#include <string>

namespace foveart::sim {

struct Config {
  uint64_t frame_budget = 0;  // 0: no budget
  bool virtual_clock = false;
  std::string gaze_file;  // empty: built-in saccade script
  bool eye_tracking = true;
  bool head_sway = false;
  // FOVEART_SIM_MOTION: "builtin" or a motion CSV path; empty: none. When set it
  // drives the head and the gaze, over head_sway and gaze_file.
  std::string motion;
  uint64_t motion_seed = 1;  // FOVEART_SIM_MOTION_SEED, for "builtin"
  std::string capture_dir;  // empty: no capture
  uint32_t capture_every = 1;
  int log_level = 1;
  bool float_formats_only = false;  // FOVEART_SIM_FORMATS=float
};

// Reads the FOVEART_SIM_* variables. On a malformed value returns nullopt and
// fills error with a message naming the variable.
std::optional<Config> config_from_environment(std::string* error);

}  // namespace foveart::sim
