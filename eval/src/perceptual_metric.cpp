// The perceptual foveated difference metric (perceptual_metric.hpp).
#include <eval/perceptual_metric.hpp>

#include "perceptual_detail.hpp"

#include <metrics/image_metrics.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace foveart::eval {

namespace {

using namespace perceptual_detail;

// The frequency (cycles per full-resolution pixel) where band b's gain peaks.
double band_peak_freq(int band) {
  double best_f = 0.0, best_g = -1.0;
  for (int i = 0; i <= 400; ++i) {
    const double f = 0.5 * std::pow(2.0, -12.0 * double(i) / 400.0);
    const double g = laplacian_band_gain(band, f);
    if (g > best_g) best_g = g, best_f = f;
  }
  return best_f;
}

// castleCSF (A -> infinity, i.e. S_peak rho sqrt(A_c)) tables of one band over luminance x eccentricity.
PerceptualMetric::BandTable band_table(int band, const PerceptualDisplay& d, int ecc_steps, EccentricityTerm term) {
  PerceptualMetric::BandTable t;
  t.freq_cyc_px = band_peak_freq(band);
  const double rho0 = t.freq_cyc_px * d.pixels_per_deg;
  t.pool_sigma_px = std::sqrt(castle_critical_area_deg2(rho0) / (2.0 * std::numbers::pi)) * d.pixels_per_deg /
                    std::ldexp(1.0, band);
  t.log_s_nasal.resize(std::size_t(kLumSteps * ecc_steps));
  t.log_s_temporal.resize(t.log_s_nasal.size());
  for (int e = 0; e < ecc_steps; ++e) {
    const double ecc = std::min(89.0, e * kEccStepDeg);
    const double rho = t.freq_cyc_px * local_ppd(d.pixels_per_deg, ecc);
    for (int l = 0; l < kLumSteps; ++l) {
      const double lum = std::pow(10.0, kLogLumMin + l * kLogLumStep);
      const std::size_t i = std::size_t(e * kLumSteps + l);
      t.log_s_nasal[i] = float(std::log10(castle_sensitivity({rho, lum, 1e9, ecc, 180.0}, term)));
      t.log_s_temporal[i] = float(std::log10(castle_sensitivity({rho, lum, 1e9, ecc, 0.0}, term)));
    }
  }
  return t;
}

}  // namespace

bool PerceptualMetric::create(const PerceptualDisplay& display, int max_width_px, int max_height_px,
                              const PerceptualOptions& options, PerceptualMetric& out, std::string& error) {
  if (!(display.pixels_per_deg > 0.0) || !std::isfinite(display.pixels_per_deg))
    return error = "perceptual metric: pixels per degree must be positive and finite", false;
  if (!(display.white_luminance_cd_m2 > 0.0) || !std::isfinite(display.white_luminance_cd_m2))
    return error = "perceptual metric: the white luminance must be positive and finite (cd/m^2)", false;
  if (!(display.black_luminance_cd_m2 >= 0.0) || !(display.black_luminance_cd_m2 < display.white_luminance_cd_m2))
    return error = "perceptual metric: the black luminance must be in [0, white) cd/m^2", false;
  if (max_width_px < kMinBandSidePx || max_height_px < kMinBandSidePx)
    return error = "perceptual metric: images must be at least 8x8 pixels", false;
  out = PerceptualMetric{};
  out.display_ = display;
  out.options_ = options;
  out.max_width_px_ = max_width_px;
  out.max_height_px_ = max_height_px;
  const double view_distance_px = display.pixels_per_deg * kDegPerRad;
  const double ecc_max = ecc_of_distance(std::hypot(double(max_width_px), double(max_height_px)), view_distance_px);
  const int ecc_steps = int(std::ceil(ecc_max / kEccStepDeg)) + 2;
  out.ecc_steps_ = ecc_steps;
  for (int b = 0; (std::min(max_width_px, max_height_px) >> (b + 1)) >= kMinBandSidePx / 2; ++b)
    out.bands_.push_back(band_table(b, display, ecc_steps, options.eccentricity));
  // A sinusoid of contrast c at a middle band's peak carries c^2 / 2 x sum_b gain_b^2 of band energy.
  const int mid = int(out.bands_.size()) / 2;
  double gain2 = 0.0;
  for (int b = 0; b < int(out.bands_.size()); ++b) {
    const double g = laplacian_band_gain(b, out.bands_[std::size_t(mid)].freq_cyc_px);
    gain2 += g * g;
  }
  out.energy_scale_ = 2.0 / gain2;
  return true;
}

}  // namespace foveart::eval
