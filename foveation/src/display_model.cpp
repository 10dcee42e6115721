// Display construction, validation and presets (thesis 4.1; FOVE/Vive numbers
// from docs/design.md "Numbers to keep at hand").
#include "foveation/display_model.hpp"

#include "foveation/device.hpp"

#include <algorithm>
#include <array>
#include <limits>
#include <sstream>

namespace foveart::foveation {
namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;

// Viewing distance (pixels) at which the thesis's counts of Table 1 are
// reproduced on a 1280 x 1440 screen (v = D / N); see docs/foveation.md.
constexpr double kThesisViewDistanceWidths = 0.85;

}  // namespace

DisplayModel DisplayModel::from_fov(int width_px, int height_px, double horizontal_fov_deg) {
  DisplayModel d;
  d.width_px = width_px;
  d.height_px = height_px;
  // Pinhole: half the width subtends half the field of view.
  d.view_distance_px = 0.5 * width_px / std::tan(0.5 * horizontal_fov_deg / kDegPerRad);
  if (!(horizontal_fov_deg > 0.0 && horizontal_fov_deg < 180.0)) d.view_distance_px = std::nan("");
  return d;
}

DisplayModel DisplayModel::from_pixels_per_degree(int width_px, int height_px, double pixels_per_degree) {
  DisplayModel d;
  d.width_px = width_px;
  d.height_px = height_px;
  // At the centre one degree spans D * (pi / 180) pixels.
  d.view_distance_px = pixels_per_degree * kDegPerRad;
  return d;
}

DisplayModel DisplayModel::from_thesis(int width_px, int height_px, double view_distance_widths) {
  DisplayModel d;
  d.width_px = width_px;
  d.height_px = height_px;
  d.view_distance_px = double(width_px) * view_distance_widths;  // eq. 1: N v
  return d;
}

double DisplayModel::horizontal_fov_deg() const {
  return 2.0 * std::atan(0.5 * width_px / view_distance_px) * kDegPerRad;
}

double DisplayModel::pixel_grid_radius_px() const {
  if (fovea_pattern != FoveaPattern::kPixelGrid) return 0.0;
  const double ecc_deg = pixel_grid_ecc_deg(display_cpd(), csf);
  if (!(ecc_deg > 0.0)) return 0.0;
  // Invert eq. 1 with its scale: e = atan(d / D) * scale.
  const double angle_rad = ecc_deg / scale / kDegPerRad;
  if (angle_rad >= 0.5 * std::numbers::pi) return std::numeric_limits<double>::infinity();
  return view_distance_px * std::tan(angle_rad);
}

double DisplayModel::exact_fovea_radius_px() const {
  DisplayModel thesis_density = *this;
  thesis_density.scale = std::max(scale, 1.0);
  return thesis_density.pixel_grid_radius_px();
}

std::string_view fovea_pattern_name(FoveaPattern pattern) {
  return pattern == FoveaPattern::kThesisPoisson ? "thesis" : "pixel-grid";
}

std::optional<FoveaPattern> parse_fovea_pattern(std::string_view name) {
  if (name == "pixel-grid") return FoveaPattern::kPixelGrid;
  if (name == "thesis") return FoveaPattern::kThesisPoisson;
  return std::nullopt;
}

std::string DisplayModel::validate() const {
  std::ostringstream err;
  if (width_px <= 0 || height_px <= 0) {
    err << "display size must be positive (got " << width_px << "x" << height_px << ")";
  } else if (width_px > 16384 || height_px > 16384) {
    err << "display size " << width_px << "x" << height_px << " exceeds 16384 pixels per side";
  } else if (!std::isfinite(view_distance_px) || view_distance_px <= 0.0) {
    err << "viewing distance must be finite and positive (field of view below 180 degrees, "
           "pixels per degree > 0)";
  } else if (!std::isfinite(scale) || scale <= 0.0) {
    err << "density scale must be finite and > 0 (got " << scale << ")";
  } else if (!(csf.ct0 > 0.0 && csf.ct0 < 1.0) || !(csf.alpha > 0.0) || !(csf.e2_deg > 0.0)) {
    err << "CSF parameters out of range (need 0 < CT0 < 1, alpha > 0, e2 > 0)";
  }
  return err.str();
}

std::optional<DisplayModel> display_preset(std::string_view name) {
  DisplayModel d;
  if (name == "fove") {
    // The headset the simulated runtime reports (foveation/device.hpp): same pixels,
    // same horizontal FOV, and square pixels make the vertical FOV agree as well.
    const HeadsetDescription fove = fove0();
    d = DisplayModel::from_fov(fove.eye_width_px, fove.eye_height_px, fove.horizontal_fov_rad() * kDegPerRad);
  } else if (name == "vive") {
    d = DisplayModel::from_fov(1080, 1200, 110.0);  // HTC Vive: 2160x1200, ~110 deg
  } else if (name == "thesis") {
    d = DisplayModel::from_thesis(1280, 1440, kThesisViewDistanceWidths);
    d.fovea_pattern = FoveaPattern::kThesisPoisson;
  } else {
    return std::nullopt;
  }
  d.name = std::string(name);
  return d;
}

std::vector<std::string> display_preset_names() { return {"fove", "vive", "thesis"}; }

}  // namespace foveart::foveation
