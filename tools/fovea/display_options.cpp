#include "display_options.hpp"

namespace foveart::fovea {

void add_display_options(CLI::App* cmd, DisplayOptions& o) {
  std::string presets;
  for (const auto& n : foveation::display_preset_names()) presets += (presets.empty() ? "" : ", ") + n;
  cmd->add_option("--preset", o.preset, "display preset: " + presets)->capture_default_str();
  cmd->add_option("--width", o.width_px, "per-eye width in pixels (overrides the preset)");
  cmd->add_option("--height", o.height_px, "per-eye height in pixels (overrides the preset)");
  auto* fov = cmd->add_option("--fov-deg", o.fov_deg, "horizontal field of view in degrees");
  cmd->add_option("--pixels-per-degree", o.pixels_per_degree, "pixels per degree at the centre")->excludes(fov);
  cmd->add_option("--scale", o.scale, "density scale (multiplies eccentricity)")->capture_default_str();
  cmd->add_option("--disc-rule", o.disc_rule, "min-distance (thesis Table 1) or non-overlapping")
      ->capture_default_str();
  cmd->add_option("--seed", o.seed, "point set seed")->capture_default_str();
}

foveation::DisplayModel resolve_display(const DisplayOptions& o) {
  auto preset = foveation::display_preset(o.preset);
  if (!preset) throw CLI::ValidationError("--preset", "unknown preset '" + o.preset + "'");
  foveation::DisplayModel d = *preset;
  const int w = o.width_px != 0 ? o.width_px : d.width_px;
  const int h = o.height_px != 0 ? o.height_px : d.height_px;
  if (w <= 0 || h <= 0) {
    throw CLI::ValidationError("--width/--height", "sizes must be positive, got " + std::to_string(w) + "x" +
                                                       std::to_string(h));
  }
  if (o.fov_deg != 0.0) {
    if (!(o.fov_deg > 0.0 && o.fov_deg < 180.0)) {
      throw CLI::ValidationError("--fov-deg", "field of view must be in (0, 180) degrees, got " +
                                                  std::to_string(o.fov_deg));
    }
    d = foveation::DisplayModel::from_fov(w, h, o.fov_deg);
  } else if (o.pixels_per_degree != 0.0) {
    if (!(o.pixels_per_degree > 0.0)) {
      throw CLI::ValidationError("--pixels-per-degree", "must be > 0");
    }
    d = foveation::DisplayModel::from_pixels_per_degree(w, h, o.pixels_per_degree);
  } else if (w != d.width_px || h != d.height_px) {
    // New size, same angular resolution as the preset.
    const double ppd = d.view_distance_px * 3.141592653589793 / 180.0;
    d = foveation::DisplayModel::from_pixels_per_degree(w, h, ppd);
  }
  d.name = (o.fov_deg != 0.0 || o.pixels_per_degree != 0.0 || o.width_px != 0 || o.height_px != 0)
               ? "custom"
               : o.preset;
  if (!(o.scale > 0.0) || !std::isfinite(o.scale)) {
    throw CLI::ValidationError("--scale", "density scale must be > 0, got " + std::to_string(o.scale));
  }
  d.scale = o.scale;
  if (o.disc_rule == "min-distance") {
    d.disc_rule = foveation::DiscRule::kMinDistance;
  } else if (o.disc_rule == "non-overlapping") {
    d.disc_rule = foveation::DiscRule::kNonOverlapping;
  } else {
    throw CLI::ValidationError("--disc-rule", "expected min-distance or non-overlapping, got '" + o.disc_rule + "'");
  }
  if (auto err = d.validate(); !err.empty()) throw CLI::ValidationError("display", err);
  return d;
}

}  // namespace foveart::fovea
