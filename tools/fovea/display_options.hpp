// Command-line options that choose a display and a point set, shared by the
// fovea subcommands.
#pragma once

#include <cstdint>
#include <string>

#include <CLI/CLI.hpp>

#include "foveation/display_model.hpp"

namespace foveart::fovea {

struct DisplayOptions {
  std::string preset = "fove";
  int width_px = 0;   // 0: from the preset
  int height_px = 0;
  double fov_deg = 0.0;
  double pixels_per_degree = 0.0;
  double scale = 1.0;
  std::string disc_rule = "min-distance";
  std::uint64_t seed = 1;
};

// Adds --preset --width --height --fov-deg --pixels-per-degree --scale --disc-rule --seed.
void add_display_options(CLI::App* cmd, DisplayOptions& opts);

// The display the options describe; throws CLI::ValidationError with a clear message.
foveation::DisplayModel resolve_display(const DisplayOptions& opts);

}  // namespace foveart::fovea
