// Display and eye model: eccentricity, contrast-sensitivity cut-off, display
// Nyquist and point spacing (thesis section 4.1, eqs. 1-4).
//
// Every length is in pixels of one eye's image. The whole display geometry the
// model needs is one number, the viewing distance in pixels D = N * v (thesis:
// N = display width in pixels, v = viewing distance in display widths); a
// display given by field of view or by pixels per degree is converted to D.
#pragma once

#include <cmath>
#include <numbers>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace foveart::foveation {

// Model constants of Wang et al. 2001 after Geisler & Perry 1998 (thesis eq. 2).
struct CsfParams {
  double ct0 = 1.0 / 64.0;  // minimal contrast threshold
  double alpha = 0.106;     // spatial frequency decay constant
  double e2_deg = 2.3;      // half-resolution eccentricity
};

// a = sqrt(1/pi): radius of a disc whose area is one pixel (thesis eq. 4).
inline constexpr double kPixelDiscRadiusPx = 0.56418958354775628;  // 1/sqrt(pi)

// Thesis eq. 1: e = atan(d / (N v)), in radians, returned in degrees and
// multiplied by the density scale (thesis 4.1: "scales the resulting eccentricity").
inline double eccentricity_deg(double distance_px, double view_distance_px, double scale = 1.0) {
  return std::atan(distance_px / view_distance_px) * (180.0 / std::numbers::pi) * scale;
}

// Thesis eq. 2: f_c = e2 ln(1/CT0) / ((e + e2) alpha), cycles per degree.
inline double cutoff_frequency_cpd(double ecc_deg, const CsfParams& csf = {}) {
  return csf.e2_deg * std::log(1.0 / csf.ct0) / ((ecc_deg + csf.e2_deg) * csf.alpha);
}

// Thesis eq. 3: f_d = pi N v / 360, the display's Nyquist frequency in cycles per degree.
inline double display_nyquist_cpd(double view_distance_px) {
  return std::numbers::pi * view_distance_px / 360.0;
}

// Thesis eq. 4: p = f_d / f_c0 - (1 - a) with f_c0 = min(f_d, f_c); the radius of a
// point's disc in pixels (a at the fovea, growing with eccentricity).
inline double point_radius_px(double display_cpd, double cutoff_cpd) {
  const double fc0 = std::fmin(display_cpd, cutoff_cpd);
  return display_cpd / fc0 - (1.0 - kPixelDiscRadiusPx);
}

// How two points' discs may meet (the thesis does not say; docs/foveation.md).
enum class DiscRule : int {
  // |x_i - x_j| >= max(r_i, r_j): p is the Poisson-disc distance. Reproduces the
  // counts of thesis Table 1; the default.
  kMinDistance = 0,
  // |x_i - x_j| >= r_i + r_j: p is the radius of a disc no other disc overlaps,
  // so at most one point per pixel at the fovea (the intent stated for eq. 4).
  kNonOverlapping = 1,
};

// Smallest allowed distance between two points of radii r_i and r_j.
inline float min_point_distance_px(DiscRule rule, float ri, float rj) {
  return rule == DiscRule::kNonOverlapping ? ri + rj : std::fmax(ri, rj);
}

// What samples the fovea (docs/foveation.md, "The pixel-exact fovea").
enum class FoveaPattern : int {
  // Where the eye resolves every pixel (f_c >= f_d, eqs. 2-4) one point at each
  // pixel centre, sampled over the pixel's own square; beyond it the perceptual
  // Poisson set, at most one point per pixel. The default.
  kPixelGrid = 0,
  // The thesis's reading: the Poisson set everywhere with p as its minimum
  // distance (reproduces thesis Table 1; about two points per pixel at the fovea).
  kThesisPoisson = 1,
};

// "pixel-grid" | "thesis", as the command-line tools spell them.
std::string_view fovea_pattern_name(FoveaPattern pattern);
std::optional<FoveaPattern> parse_fovea_pattern(std::string_view name);

// Largest eccentricity (degrees, scaled like eccentricity_deg) at which the
// CSF cut-off still reaches the display's Nyquist frequency: f_c(e) = f_d
// solved for e (eqs. 2-3). Negative when even the fovea does not resolve a pixel.
inline double pixel_grid_ecc_deg(double display_cpd, const CsfParams& csf = {}) {
  return csf.e2_deg * std::log(1.0 / csf.ct0) / (csf.alpha * display_cpd) - csf.e2_deg;
}

// One eye's display as the foveation sees it.
struct DisplayModel {
  std::string name = "custom";
  int width_px = 0;   // per eye
  int height_px = 0;  // per eye
  double view_distance_px = 0.0;  // D = N v; pixels per degree at the centre = D pi / 180
  double scale = 1.0;             // density scaling factor, multiplies eccentricity
  DiscRule disc_rule = DiscRule::kMinDistance;
  FoveaPattern fovea_pattern = FoveaPattern::kPixelGrid;
  CsfParams csf{};

  // Display by per-eye resolution and horizontal field of view (pinhole, symmetric).
  static DisplayModel from_fov(int width_px, int height_px, double horizontal_fov_deg);
  // Display by pixels per degree at the centre of view.
  static DisplayModel from_pixels_per_degree(int width_px, int height_px, double pixels_per_degree);
  // Display by the thesis's parameters: N = width_px, v in display widths.
  static DisplayModel from_thesis(int width_px, int height_px, double view_distance_widths);

  // Canvas of the point set: 2W x 2H with the centre of interest at (W, H) (thesis 4.1).
  int canvas_width_px() const { return 2 * width_px; }
  int canvas_height_px() const { return 2 * height_px; }

  double ecc_deg(double distance_px) const {
    return eccentricity_deg(distance_px, view_distance_px, scale);
  }
  double display_cpd() const { return display_nyquist_cpd(view_distance_px); }
  double cutoff_cpd(double distance_px) const { return cutoff_frequency_cpd(ecc_deg(distance_px), csf); }
  // Disc radius of a point at distance_px from the centre of interest (eqs. 1-4).
  double radius_px(double distance_px) const {
    return point_radius_px(display_cpd(), cutoff_cpd(distance_px));
  }
  double horizontal_fov_deg() const;
  // Radius (pixels from the centre of interest) of the region the pixel grid
  // samples: where f_c >= f_d. 0 for the thesis pattern or a display whose
  // fovea does not resolve a pixel; +inf when the eye resolves every pixel.
  double pixel_grid_radius_px() const;
  // Radius of the pixel-exact fovea, whose points are always traced with all their rays:
  // the pixel grid at the thesis's density (scale 1), or the whole grid at a sparser
  // scale. A denser scale widens the grid beyond it: a margin that keeps its points but
  // whose rays content-aware density reduces as a Poisson point's (docs/content_density.md).
  double exact_fovea_radius_px() const;

  // Empty string when usable, else what is wrong (sizes, FOV, scale, finite values).
  std::string validate() const;
};

// Named presets: "fove", "vive", "thesis" (the thesis's display and its
// Poisson reading, FoveaPattern::kThesisPoisson). Empty for an unknown name.
std::optional<DisplayModel> display_preset(std::string_view name);
std::vector<std::string> display_preset_names();

}  // namespace foveart::foveation
