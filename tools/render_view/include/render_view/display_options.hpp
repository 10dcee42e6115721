// Command-line options that choose a display and a point set, shared by the
// fovea subcommands.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "foveation/display_model.hpp"
#include "foveation/ray_samples.hpp"

namespace foveart::render_view {

// An unset option takes the preset's value; a given one must be valid (a
// zero or negative size is an error, never "unset").
struct DisplayOptions {
  std::string preset = "fove";
  std::optional<int> width_px;   // > 0
  std::optional<int> height_px;  // > 0
  std::optional<double> fov_deg;            // horizontal, in (0, 180)
  std::optional<double> pixels_per_degree;  // > 0, finite
  double density_scale = 1.0;               // > 0, finite
  std::string disc_rule = "min-distance";
  std::optional<std::string> pattern;       // pixel-grid | thesis; unset: the preset's
  std::uint64_t seed = 1;
};

// Adds --preset --width --height --fov-deg --pixels-per-degree --density-scale --disc-rule --pattern --seed.
void add_display_options(CLI::App* cmd, DisplayOptions& opts);

// --pattern alone, for commands with their own display options (fovea render).
void add_pattern_option(CLI::App* cmd, std::optional<std::string>& pattern);
// The pattern given, or nullopt when unset; throws CLI::ValidationError for a bad name.
std::optional<foveation::FoveaPattern> resolve_pattern(const std::optional<std::string>& pattern);

// --pixel-filter box|bspline2 into *filter (foveation/ray_samples.hpp), its
// current value the default; a bad name is a CLI::ValidationError naming it.
void add_pixel_filter_option(CLI::App* cmd, foveation::PixelFilter* filter);

// The display the options describe; throws CLI::ValidationError naming the
// option and the bad value.
foveation::DisplayModel resolve_display(const DisplayOptions& opts);

}  // namespace foveart::render_view
