#include <render_view/display_options.hpp>

#include <cmath>
#include <sstream>

namespace foveart::render_view {
namespace {

template <typename T>
std::string text_of(T value) {
  std::ostringstream s;
  s << value;
  return s.str();
}

// A given size must be a positive number of pixels; unset takes the preset's.
int size_px(const std::optional<int>& given, int preset_px, const char* option) {
  if (!given) return preset_px;
  if (*given <= 0) throw CLI::ValidationError(option, "must be a positive number of pixels, got " + text_of(*given));
  return *given;
}

}  // namespace

void add_display_options(CLI::App* cmd, DisplayOptions& o) {
  std::string presets;
  for (const auto& n : foveation::display_preset_names()) presets += (presets.empty() ? "" : ", ") + n;
  cmd->add_option("--preset", o.preset, "display preset: " + presets)->capture_default_str();
  cmd->add_option("--width", o.width_px, "per-eye width in pixels, > 0 (overrides the preset)");
  cmd->add_option("--height", o.height_px, "per-eye height in pixels, > 0 (overrides the preset)");
  auto* fov = cmd->add_option("--fov-deg", o.fov_deg, "horizontal field of view in degrees, in (0, 180)");
  cmd->add_option("--pixels-per-degree", o.pixels_per_degree, "pixels per degree at the centre, > 0")->excludes(fov);
  cmd->add_option("--density-scale", o.density_scale, "density scale (multiplies eccentricity), > 0")
      ->capture_default_str();
  cmd->add_option("--disc-rule", o.disc_rule, "min-distance (thesis Table 1) or non-overlapping")
      ->capture_default_str();
  add_pattern_option(cmd, o.pattern);
  cmd->add_option("--seed", o.seed, "point set seed")->capture_default_str();
}

void add_pattern_option(CLI::App* cmd, std::optional<std::string>& pattern) {
  cmd->add_option("--pattern", pattern,
                  "fovea sampling: pixel-grid (one point per pixel where the eye resolves pixels; default) or "
                  "thesis (Poisson everywhere, thesis Table 1; the thesis preset's)");
}

void add_pixel_filter_option(CLI::App* cmd, foveation::PixelFilter* filter) {
  cmd->add_option_function<std::string>(
         "--pixel-filter", [filter](const std::string& name) { foveation::parse_pixel_filter(name, filter); },
         "What a pixel's rays follow, the reference's too: box (uniform over the pixel, sharpest) or bspline2 "
         "(quadratic B-spline, 3 px wide: softer, steadier while the head moves)")
      ->check(CLI::Validator(
          [](std::string& name) {
            foveation::PixelFilter parsed{};
            return foveation::parse_pixel_filter(name, &parsed) ? std::string()
                                                                : "'" + name + "' is not box or bspline2";
          },
          "box|bspline2"))
      ->default_str(foveation::pixel_filter_name(*filter));
}

std::optional<foveation::FoveaPattern> resolve_pattern(const std::optional<std::string>& pattern) {
  if (!pattern) return std::nullopt;
  const auto parsed = foveation::parse_fovea_pattern(*pattern);
  if (!parsed) throw CLI::ValidationError("--pattern", "expected pixel-grid or thesis, got '" + *pattern + "'");
  return parsed;
}

foveation::DisplayModel resolve_display(const DisplayOptions& o) {
  auto preset = foveation::display_preset(o.preset);
  if (!preset) throw CLI::ValidationError("--preset", "unknown preset '" + o.preset + "'");
  foveation::DisplayModel d = *preset;
  const foveation::FoveaPattern preset_pattern = d.fovea_pattern;
  const int w = size_px(o.width_px, d.width_px, "--width");
  const int h = size_px(o.height_px, d.height_px, "--height");
  if (o.fov_deg) {
    if (!(*o.fov_deg > 0.0 && *o.fov_deg < 180.0)) {
      throw CLI::ValidationError("--fov-deg", "field of view must be in (0, 180) degrees, got " + text_of(*o.fov_deg));
    }
    d = foveation::DisplayModel::from_fov(w, h, *o.fov_deg);
  } else if (o.pixels_per_degree) {
    if (!(*o.pixels_per_degree > 0.0) || !std::isfinite(*o.pixels_per_degree)) {
      throw CLI::ValidationError("--pixels-per-degree",
                                 "must be a finite number > 0, got " + text_of(*o.pixels_per_degree));
    }
    d = foveation::DisplayModel::from_pixels_per_degree(w, h, *o.pixels_per_degree);
  } else if (w != d.width_px || h != d.height_px) {
    // New size, same angular resolution as the preset.
    const double ppd = d.view_distance_px * 3.141592653589793 / 180.0;
    d = foveation::DisplayModel::from_pixels_per_degree(w, h, ppd);
  }
  d.name = (o.fov_deg || o.pixels_per_degree || o.width_px || o.height_px) ? "custom" : o.preset;
  if (!(o.density_scale > 0.0) || !std::isfinite(o.density_scale)) {
    throw CLI::ValidationError("--density-scale", "must be a finite number > 0, got " + text_of(o.density_scale));
  }
  d.scale = o.density_scale;
  if (o.disc_rule == "min-distance") {
    d.disc_rule = foveation::DiscRule::kMinDistance;
  } else if (o.disc_rule == "non-overlapping") {
    d.disc_rule = foveation::DiscRule::kNonOverlapping;
  } else {
    throw CLI::ValidationError("--disc-rule", "expected min-distance or non-overlapping, got '" + o.disc_rule + "'");
  }
  d.fovea_pattern = resolve_pattern(o.pattern).value_or(preset_pattern);
  if (auto err = d.validate(); !err.empty()) throw CLI::ValidationError("display", err);
  return d;
}

}  // namespace foveart::render_view
