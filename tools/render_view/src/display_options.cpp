// The display options and their parsers (display_options.hpp).
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

// "A,B,..." -> numbers; false when an item is not a number.
[[nodiscard]] bool parse_numbers(const std::string& text, std::vector<double>* out) {
  std::istringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    std::istringstream one(item);
    double v = 0.0;
    if (!(one >> v) || !(one >> std::ws).eof()) return false;
    out->push_back(v);
  }
  return !out->empty() && text.back() != ',';
}

std::string fail(std::string* error, std::string message) {
  *error = std::move(message);
  return *error;
}

}  // namespace

bool parse_size(const std::string& text, glm::ivec2* size, std::string* error) {
  std::istringstream in(text);
  long w = 0, h = 0;
  char x = 0;
  const bool shaped = static_cast<bool>(in >> w >> x >> h) && x == 'x' && (in >> std::ws).eof() &&
                      text.find_first_of("+-. ") == std::string::npos;
  if (!shaped || w <= 0 || h <= 0 || w > 65536 || h > 65536) {
    fail(error, "expected WxH, whole pixels from 1 to 65536 each (e.g. 320x360), got '" + text + "'");
    return false;
  }
  *size = glm::ivec2(static_cast<int>(w), static_cast<int>(h));
  return true;
}

double FovDeg::horizontal_span() const {
  if (angles) return (*angles)[1] - (*angles)[0];
  return horizontal.value_or(0.0);
}

std::string fov_deg_problem(const FovDeg& fov) {
  if (fov.horizontal && !(*fov.horizontal > 0.0 && *fov.horizontal < 180.0))
    return "the horizontal field of view must be in (0, 180) degrees, got " + text_of(*fov.horizontal);
  if (!fov.angles) return "";
  const auto& f = *fov.angles;
  for (double a : f)
    if (!std::isfinite(a) || a <= -90.0 || a >= 90.0)
      return "the angles L,R,U,D must be finite and inside (-90, 90) degrees, got " + text_of(a);
  if (!(f[0] < f[1])) return "left must be less than right";
  if (!(f[3] < f[2])) return "down must be less than up";
  return "";
}

bool parse_fov_deg(const std::string& text, FovDeg* fov, std::string* error) {
  std::vector<double> v;
  if (!parse_numbers(text, &v) || (v.size() != 1 && v.size() != 4)) {
    fail(error, "expected one number H (the horizontal field of view) or four L,R,U,D (an OpenXR frustum), got '" +
                    text + "'");
    return false;
  }
  FovDeg parsed;
  if (v.size() == 1)
    parsed.horizontal = v[0];
  else
    parsed.angles = std::array<double, 4>{v[0], v[1], v[2], v[3]};
  if (const std::string bad = fov_deg_problem(parsed); !bad.empty()) {
    fail(error, bad);
    return false;
  }
  *fov = parsed;
  return true;
}

void add_renamed_option(CLI::App* cmd, const std::string& old_name, const std::string& replacement) {
  cmd->add_option_function<std::string>(
         old_name,
         [old_name, replacement](const std::string&) {
           throw CLI::ValidationError(old_name, "no longer an option here: give " + replacement);
         },
         "")
      ->group("");  // hidden from --help
}

void add_display_options(CLI::App* cmd, DisplayOptions& o) {
  std::string presets;
  for (const auto& n : foveation::display_preset_names()) presets += (presets.empty() ? "" : ", ") + n;
  cmd->add_option("--preset", o.preset, "display preset: " + presets)->capture_default_str();
  cmd->add_option("--size", o.size, "per-eye size WxH in pixels (overrides the preset's; its field of view kept)");
  auto* fov = cmd->add_option("--fov-deg", o.fov_deg,
                              "field of view in degrees: H, the horizontal span in (0, 180), or an OpenXR frustum "
                              "L,R,U,D (the point set follows its horizontal span)");
  cmd->add_option("--pixels-per-degree", o.pixels_per_degree, "pixels per degree at the centre, > 0")->excludes(fov);
  cmd->add_option("--density-scale", o.density_scale, "density scale (multiplies eccentricity), > 0")
      ->capture_default_str();
  cmd->add_option("--disc-rule", o.disc_rule, "min-distance (thesis Table 1) or non-overlapping")
      ->capture_default_str();
  add_pattern_option(cmd, o.pattern);
  cmd->add_option("--seed", o.seed, "point set seed")->capture_default_str();
  add_renamed_option(cmd, "--width", "--size WxH");
  add_renamed_option(cmd, "--height", "--size WxH");
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

namespace {

// The preset at the size and field of view asked for: the preset itself when neither is given;
// for another size its horizontal field of view at that size (as `fovea render --size`).
std::optional<foveation::DisplayModel> sized_display(const DisplayOptions& o, const foveation::DisplayModel& preset,
                                                     std::string* error) {
  glm::ivec2 size(preset.width_px, preset.height_px);
  if (!o.size.empty() && !parse_size(o.size, &size, error)) {
    *error = "--size: " + *error;
    return std::nullopt;
  }
  if (!o.fov_deg.empty()) {
    FovDeg fov;
    if (!parse_fov_deg(o.fov_deg, &fov, error)) {
      *error = "--fov-deg: " + *error;
      return std::nullopt;
    }
    return foveation::DisplayModel::from_fov(size.x, size.y, fov.horizontal_span());
  }
  if (o.pixels_per_degree) {
    if (!(*o.pixels_per_degree > 0.0) || !std::isfinite(*o.pixels_per_degree)) {
      *error = "--pixels-per-degree: must be a finite number > 0, got " + text_of(*o.pixels_per_degree);
      return std::nullopt;
    }
    return foveation::DisplayModel::from_pixels_per_degree(size.x, size.y, *o.pixels_per_degree);
  }
  if (size == glm::ivec2(preset.width_px, preset.height_px)) return preset;
  return foveation::DisplayModel::from_fov(size.x, size.y, preset.horizontal_fov_deg());
}

}  // namespace

std::optional<foveation::DisplayModel> resolve_display(const DisplayOptions& o, std::string* error) {
  const std::optional<foveation::DisplayModel> preset = foveation::display_preset(o.preset);
  if (!preset) {
    *error = "--preset: unknown preset '" + o.preset + "'";
    return std::nullopt;
  }
  std::optional<foveation::DisplayModel> d = sized_display(o, *preset, error);
  if (!d) return std::nullopt;
  d->name = (!o.size.empty() || !o.fov_deg.empty() || o.pixels_per_degree) ? "custom" : o.preset;
  if (!(o.density_scale > 0.0) || !std::isfinite(o.density_scale)) {
    *error = "--density-scale: must be a finite number > 0, got " + text_of(o.density_scale);
    return std::nullopt;
  }
  d->scale = o.density_scale;
  if (o.disc_rule == "min-distance") {
    d->disc_rule = foveation::DiscRule::kMinDistance;
  } else if (o.disc_rule == "non-overlapping") {
    d->disc_rule = foveation::DiscRule::kNonOverlapping;
  } else {
    *error = "--disc-rule: expected min-distance or non-overlapping, got '" + o.disc_rule + "'";
    return std::nullopt;
  }
  d->fovea_pattern = preset->fovea_pattern;
  if (o.pattern) {
    const std::optional<foveation::FoveaPattern> pattern = foveation::parse_fovea_pattern(*o.pattern);
    if (!pattern) {
      *error = "--pattern: expected pixel-grid or thesis, got '" + *o.pattern + "'";
      return std::nullopt;
    }
    d->fovea_pattern = *pattern;
  }
  if (const std::string bad = d->validate(); !bad.empty()) {
    *error = "display: " + bad;
    return std::nullopt;
  }
  return d;
}

}  // namespace foveart::render_view
