// Command-line options that choose a display, one spelling for every command of
// `fovea` and `fovea-eval`: --preset, --size WxH (the per-eye size in pixels)
// and --fov-deg H | L,R,U,D (the field of view in degrees); the point set
// options of `fovea pointset`; and the parsers of their values.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include <glm/ext/vector_int2.hpp>

#include "foveation/display_model.hpp"
#include "foveation/ray_samples.hpp"

namespace foveart::render_view {

// "WxH" -> whole pixels, each > 0 (e.g. 320x360); false and *error quoting the text.
[[nodiscard]] bool parse_size(const std::string& text, glm::ivec2* size, std::string* error);

// --fov-deg: the field of view in degrees. One number: the horizontal span of a
// frustum symmetric about the view axis, in (0, 180) (its vertical span follows
// from the size: square pixels). Four: an exact OpenXR frustum L,R,U,D (XrFovf
// angles, each in (-90, 90), left < right, down < up). A point set follows the
// horizontal span either way, as the layer's (foveation::display_of_view).
struct FovDeg {
  std::optional<double> horizontal;
  std::optional<std::array<double, 4>> angles;  // left, right, up, down
  bool given() const { return horizontal.has_value() || angles.has_value(); }
  // `horizontal`, or right - left.
  double horizontal_span() const;
};
// "H" or "L,R,U,D"; false and *error quoting the text.
[[nodiscard]] bool parse_fov_deg(const std::string& text, FovDeg* fov, std::string* error);
// What is wrong with a field of view, "" when nothing (the checks parse_fov_deg applies).
std::string fov_deg_problem(const FovDeg& fov);

// An option renamed or moved: `old_name` stays, hidden, and giving it is an
// error naming its replacement ("--width: no longer an option here: give --size
// WxH"; "--reference-spp: ... give fovea-eval accuracy --reference-spp"), so an
// old command line fails clearly instead of meaning something else or nothing.
void add_renamed_option(CLI::App* cmd, const std::string& old_name, const std::string& replacement);

// `fovea pointset`'s display. An unset option takes the preset's value; a given
// one must be valid (a zero or negative size is an error, never "unset").
struct DisplayOptions {
  std::string preset = "fove";
  std::string size;                         // "WxH"; empty: the preset's (the preset's field of view kept)
  std::string fov_deg;                      // "H" or "L,R,U,D"; empty: the preset's
  std::optional<double> pixels_per_degree;  // > 0, finite; instead of --fov-deg
  double density_scale = 1.0;               // > 0, finite
  std::string disc_rule = "min-distance";
  std::optional<std::string> pattern;       // pixel-grid | thesis; unset: the preset's
  std::uint64_t seed = 1;
};

// Adds --preset --size --fov-deg --pixels-per-degree --density-scale --disc-rule --pattern --seed
// (and the renamed --width and --height).
void add_display_options(CLI::App* cmd, DisplayOptions& opts);

// --pattern alone, for commands with their own display options.
void add_pattern_option(CLI::App* cmd, std::optional<std::string>& pattern);

// --pixel-filter box|bspline2 into *filter (foveation/ray_samples.hpp), its
// current value the default; a bad name is a CLI::ValidationError naming it.
void add_pixel_filter_option(CLI::App* cmd, foveation::PixelFilter* filter);

// The display the options describe; nullopt and *error naming the option and the bad value.
[[nodiscard]] std::optional<foveation::DisplayModel> resolve_display(const DisplayOptions& opts, std::string* error);

}  // namespace foveart::render_view
