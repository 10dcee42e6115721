// The perceptual foveated difference metric (perceptual_metric.hpp).
#include <eval/perceptual_metric.hpp>

#include "perceptual_detail.hpp"

#include <metrics/image_metrics.hpp>

#include <algorithm>
#include <cmath>
#include <array>
#include <numbers>

namespace foveart::eval {

namespace {

using namespace perceptual_detail;

// Band b's centre frequency (cycles per full-resolution pixel): where its gain peaks.
double band_centre_freq(int band) {
  double best_f = 0.0, best_g = -1.0;
  for (int i = 0; i <= 1200; ++i) {
    const double f = 0.5 * std::pow(2.0, -12.0 * double(i) / 1200.0);
    const double g = laplacian_band_gain(band, f);
    if (g > best_g) best_g = g, best_f = f;
  }
  return best_f;
}

// Non-negative least squares, min |A w - 1|^2 over w >= 0, from the normal equations Q = A^T A,
// r = A^T 1 (Lawson & Hanson 1974, ch. 23): at most a dozen unknowns.
std::vector<double> nnls(const std::vector<double>& q, const std::vector<double>& r, int n) {
  std::vector<double> w(std::size_t(n), 0.0);
  std::vector<double> z(std::size_t(n), 0.0);
  std::vector<bool> passive(std::size_t(n), false);
  const auto solve_passive = [&] {  // z_P = Q_PP^-1 r_P, Gauss-Jordan with partial pivoting
    std::vector<int> idx;
    for (int i = 0; i < n; ++i) if (passive[std::size_t(i)]) idx.push_back(i);
    const std::size_t k = idx.size();
    std::vector<double> m(k * (k + 1));
    for (std::size_t a = 0; a < k; ++a) {
      for (std::size_t b = 0; b < k; ++b) m[a * (k + 1) + b] = q[std::size_t(idx[a] * n + idx[b])];
      m[a * (k + 1) + k] = r[std::size_t(idx[a])];
    }
    for (std::size_t c = 0; c < k; ++c) {
      std::size_t piv = c;
      for (std::size_t a = c + 1; a < k; ++a) if (std::abs(m[a * (k + 1) + c]) > std::abs(m[piv * (k + 1) + c])) piv = a;
      for (std::size_t b = 0; b <= k; ++b) std::swap(m[c * (k + 1) + b], m[piv * (k + 1) + b]);
      const double d = m[c * (k + 1) + c];
      for (std::size_t a = 0; a < k; ++a) {
        if (a == c || d == 0.0) continue;
        const double f = m[a * (k + 1) + c] / d;
        for (std::size_t b = c; b <= k; ++b) m[a * (k + 1) + b] -= f * m[c * (k + 1) + b];
      }
    }
    std::fill(z.begin(), z.end(), 0.0);
    for (std::size_t a = 0; a < k; ++a) {
      const double d = m[a * (k + 1) + a];
      z[std::size_t(idx[a])] = d != 0.0 ? m[a * (k + 1) + k] / d : 0.0;
    }
  };
  for (int outer = 0; outer < 4 * n; ++outer) {
    int j = -1;
    double best = 1e-12;
    for (int i = 0; i < n; ++i) {
      if (passive[std::size_t(i)]) continue;
      double g = r[std::size_t(i)];
      for (int k = 0; k < n; ++k) g -= q[std::size_t(i * n + k)] * w[std::size_t(k)];
      if (g > best) best = g, j = i;
    }
    if (j < 0) break;
    passive[std::size_t(j)] = true;
    for (int inner = 0; inner < 4 * n; ++inner) {
      solve_passive();
      double alpha = 1.0;
      for (int i = 0; i < n; ++i)
        if (passive[std::size_t(i)] && z[std::size_t(i)] <= 0.0)
          alpha = std::min(alpha, w[std::size_t(i)] / (w[std::size_t(i)] - z[std::size_t(i)]));
      for (int i = 0; i < n; ++i) w[std::size_t(i)] += alpha * (z[std::size_t(i)] - w[std::size_t(i)]);
      if (alpha >= 1.0) break;
      for (int i = 0; i < n; ++i)
        if (passive[std::size_t(i)] && w[std::size_t(i)] <= 1e-15) passive[std::size_t(i)] = false, w[std::size_t(i)] = 0.0;
    }
  }
  return w;
}

constexpr double kMinSolveSensitivity = 0.1;  // threshold contrast 10
constexpr double kMaxSolveFreq = 0.4;  // cycles per pixel: 2.5 pixels a cycle
constexpr int kMechanisms = PerceptualMetric::kMechanisms;

// The bands' shapes: peak frequency and, per mechanism, the pooling blur and its actual variance.
struct BandShape {
  double centre_cyc_px = 0.0;
  std::array<double, kMechanisms> pool_sigma_px{};      // band pixels, what box3_blur is asked for
  std::array<double, kMechanisms> pool_var_full_px2{};  // its actual variance, full-resolution pixels^2
};

// Frequencies (cycles per full-resolution pixel) where the bands' weights are solved: 8 per octave
// from an octave below the lowest band's centre to kMaxSolveFreq.
std::vector<double> solve_frequencies(const std::vector<BandShape>& shapes) {
  std::vector<double> f;
  const double lo = shapes.back().centre_cyc_px / 2.0;
  for (double x = kMaxSolveFreq; x >= lo; x /= std::pow(2.0, 0.125)) f.push_back(x);
  return f;
}

// A mechanism's critical area at rho for a difference flickering at omega Hz on luminance lum.
double critical_area(int mechanism, double rho, double omega_hz, double lum) {
  return mechanism == 0 ? castle_critical_area_deg2(rho, omega_hz, lum) : castle_chromatic_critical_area_deg2(rho);
}

// One table cell, one mechanism (0 achromatic, 1 chromatic share): the bands' weights w_b (squared
// sensitivities) such that a Gabor of frequency f and area A = A_c(f), the mechanism's critical
// area, gets castleCSF's response from that mechanism:
//   sum_b w_b g_b(f)^2 / 2 x A / (A + A_pool,b) = S_m(f, A)^2   (contrast 1),
// g_b the band's gain (laplacian_band_gain), g^2 / 2 a sinusoid's mean energy, A / (A + A_pool)
// the peak of the Gabor's energy envelope (area A = pi sigma^2) after the band's pooling Gaussian
// (area 2 pi s^2). Least squares in relative error over the solve frequencies, w >= 0. Gabors
// larger or smaller than A_c(f) differ from castleCSF only by the spread of A_pool,b around A_c(f).
struct SolveGrid {
  std::vector<double> freqs;  // cycles per full-resolution pixel
  std::vector<double> gain2;  // g_b(f_j)^2 / 2, freqs x bands
};

std::vector<double> cell_weights(const std::vector<BandShape>& shapes, const SolveGrid& grid,
                                 const CsfStimulus& at, double ppd_local, EccentricityTerm term, int mechanism) {
  const int n = int(shapes.size());
  const std::vector<double>& freqs = grid.freqs;
  std::vector<double> q(std::size_t(n * n), 0.0);
  std::vector<double> r(std::size_t(n), 0.0);
  std::vector<double> a(std::size_t(n), 0.0);
  for (std::size_t j = 0; j < freqs.size(); ++j) {
    const double rho = freqs[j] * ppd_local;
    const double area = critical_area(mechanism, rho, at.temporal_freq_hz, at.luminance_cd_m2);
    const CsfParts parts = castle_sensitivity_parts(
        {rho, at.luminance_cd_m2, area, at.ecc_deg, at.vis_field_deg, at.temporal_freq_hz}, term);
    // Below kMinSolveSensitivity a pattern is invisible at any contrast a display shows; aiming at that
    // floor keeps such bands quiet without letting 1 / S^2 of 1e-20 swamp the fit.
    const double s = std::max(kMinSolveSensitivity, mechanism == 0 ? parts.achromatic : parts.chromatic);
    for (int b = 0; b < n; ++b) {
      const double pool_area = 2.0 * std::numbers::pi * shapes[std::size_t(b)].pool_var_full_px2[std::size_t(mechanism)] /
                               (ppd_local * ppd_local);
      a[std::size_t(b)] = grid.gain2[j * std::size_t(n) + std::size_t(b)] * area / (area + pool_area) / (s * s);
    }
    for (int i = 0; i < n; ++i) {
      r[std::size_t(i)] += a[std::size_t(i)];
      for (int k = 0; k < n; ++k) q[std::size_t(i * n + k)] += a[std::size_t(i)] * a[std::size_t(k)];
    }
  }
  return nnls(q, r, n);
}

// Fills every band's tables (log10 sqrt w_b) over luminance x eccentricity, both fields, both mechanisms.
void solve_tables(const PerceptualDisplay& d, const std::vector<BandShape>& shapes,
                  const PerceptualMetric::TableGrid& g, const PerceptualOptions& options, foveation::Executor* ex,
                  std::vector<PerceptualMetric::BandTable>& bands) {
  SolveGrid grid{solve_frequencies(shapes), {}};
  for (const double f : grid.freqs)
    for (std::size_t b = 0; b < shapes.size(); ++b) grid.gain2.push_back(0.5 * std::pow(laplacian_band_gain(int(b), f), 2));
  const std::size_t cells = std::size_t(g.lum_steps * g.ecc_steps);
  for (auto& t : bands)
    for (std::size_t m = 0; m < std::size_t(kMechanisms); ++m) t.log_s_nasal[m].resize(cells), t.log_s_temporal[m].resize(cells);
  const auto row = [&](std::size_t e) {
    const double ecc = std::min(89.0, double(e) * kEccStepDeg);
    const double ppd_local = local_ppd(d.pixels_per_deg, ecc);
    for (int l = 0; l < g.lum_steps; ++l) {
      const double lum = std::pow(10.0, g.log_lum_min + l * kLogLumStep);
      const std::size_t i = e * std::size_t(g.lum_steps) + std::size_t(l);
      for (const double field : {180.0, 0.0})
        for (int m = 0; m < kMechanisms; ++m) {
          const std::vector<double> w = cell_weights(
              shapes, grid, {1.0, lum, 1.0, ecc, field, options.temporal_freq_hz}, ppd_local, options.eccentricity, m);
          for (std::size_t b = 0; b < bands.size(); ++b) {
            auto& table = field == 0.0 ? bands[b].log_s_temporal : bands[b].log_s_nasal;
            table[std::size_t(m)][i] = float(0.5 * std::log10(std::max(w[b], 1e-30)));
          }
        }
    }
  };
  if (ex == nullptr) {
    for (std::size_t e = 0; e < std::size_t(g.ecc_steps); ++e) row(e);
  } else {
    ex->parallel_for(std::size_t(g.ecc_steps), [&](std::size_t e) { row(e); });
  }
}

// Band b's shape on `display`: the pooling Gaussians hold each mechanism's critical area at the band's peak
// (for a flicker, on a mid-grey of the display: half its white).
BandShape band_shape(int b, const PerceptualDisplay& display, double omega_hz) {
  BandShape s;
  s.centre_cyc_px = band_centre_freq(b);
  const double rho0 = s.centre_cyc_px * display.pixels_per_deg;
  for (int m = 0; m < kMechanisms; ++m) {
    const double sigma_deg =
        std::sqrt(critical_area(m, rho0, omega_hz, 0.5 * display.white_luminance_cd_m2) / (2.0 * std::numbers::pi));
    const int level = b / kBandsPerLevel;
    s.pool_sigma_px[std::size_t(m)] = sigma_deg * display.pixels_per_deg / std::ldexp(1.0, level);
    s.pool_var_full_px2[std::size_t(m)] = box3_variance(s.pool_sigma_px[std::size_t(m)]) * std::ldexp(1.0, 2 * level);
  }
  return s;
}

}  // namespace

PerceptualDisplay view_display(const metrics::EccentricityMap& map, Eye eye) {
  PerceptualDisplay d;
  const int gx = std::clamp(int(map.gaze_px.x), 0, map.width_px - 1), gy = std::clamp(int(map.gaze_px.y), 0, map.height_px - 1);
  d.pixels_per_deg = double(map.pixels_per_deg[std::size_t(gy) * std::size_t(map.width_px) + std::size_t(gx)]);
  d.eye = eye;
  return d;
}

bool PerceptualMetric::create(const PerceptualDisplay& display, int max_width_px, int max_height_px,
                              const PerceptualOptions& options, PerceptualMetric& out, std::string& error,
                              foveation::Executor* executor) {
  if (!(display.pixels_per_deg > 0.0) || !std::isfinite(display.pixels_per_deg))
    return error = "perceptual metric: pixels per degree must be positive and finite", false;
  if (!(display.white_luminance_cd_m2 > 0.0) || !std::isfinite(display.white_luminance_cd_m2))
    return error = "perceptual metric: the white luminance must be positive and finite (cd/m^2)", false;
  if (!(display.black_luminance_cd_m2 >= 0.0) || !(display.black_luminance_cd_m2 < display.white_luminance_cd_m2))
    return error = "perceptual metric: the black luminance must be in [0, white) cd/m^2", false;
  if (max_width_px < kMinBandSidePx || max_height_px < kMinBandSidePx)
    return error = "perceptual metric: images must be at least 8x8 pixels", false;
  if (!(options.temporal_freq_hz >= 0.0) || !std::isfinite(options.temporal_freq_hz))
    return error = "perceptual metric: the temporal frequency must be finite and >= 0 Hz", false;
  out = PerceptualMetric{};
  out.gaze_cache_ = std::make_shared<GazeCache>();
  out.display_ = display;
  out.options_ = options;
  out.max_width_px_ = max_width_px;
  out.max_height_px_ = max_height_px;
  const double view_distance_px = display.pixels_per_deg * kDegPerRad;
  const double ecc_max = ecc_of_distance(std::hypot(double(max_width_px), double(max_height_px)), view_distance_px);
  out.grid_.ecc_steps = int(std::ceil(ecc_max / kEccStepDeg)) + 2;
  // Band means are blurs of luminances in [black, white]: the table spans that range and a step more.
  const double log_lo = std::floor(std::log10(std::max(display.black_luminance_cd_m2, kMinLuminance)) / kLogLumStep) * kLogLumStep;
  const double log_hi = std::max(log_lo, std::ceil(std::log10(display.white_luminance_cd_m2) / kLogLumStep) * kLogLumStep);
  out.grid_.log_lum_min = log_lo - kLogLumStep;
  out.grid_.lum_steps = int(std::lround((log_hi - log_lo) / kLogLumStep)) + 3;
  std::vector<BandShape> shapes;
  const int levels = level_count(max_width_px, max_height_px);
  for (int b = 0; b < levels * kBandsPerLevel; ++b) {
    shapes.push_back(band_shape(b, display, options.temporal_freq_hz));
    PerceptualMetric::BandTable t;
    t.freq_cyc_px = shapes.back().centre_cyc_px;
    t.pool_sigma_px = shapes.back().pool_sigma_px;
    out.bands_.push_back(std::move(t));
  }
  solve_tables(display, shapes, out.grid_, options, executor, out.bands_);
  return true;
}

}  // namespace foveart::eval
