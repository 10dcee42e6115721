// Internals of the perceptual metric shared by its two sources (perceptual_metric.hpp).
#pragma once

#include <eval/perceptual_metric.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <numbers>

namespace foveart::eval::perceptual_detail {

inline constexpr double kDegPerRad = 180.0 / std::numbers::pi;
// The tables' luminance axis: the display's range (black .. white, black at least kMinLuminance,
// below the castleCSF data's 2e-5 cd/m^2), a step beyond each end, kLogLumStep apart.
inline constexpr double kMinLuminance = 1e-5, kLogLumStep = 0.125;
inline constexpr double kEccStepDeg = 1.0;
// ColorVideoVDP's (Mantiuk et al. 2024) achromatic sustained masking: p, q and k = 10^c.
inline constexpr double kMaskP = 2.264355;
inline constexpr double kMaskQ = 1.302623;
inline const double kMaskK = std::pow(10.0, -0.795497);
inline constexpr double kPsychometricBeta = 3.5;  // Weibull slope of detection (Robson & Graham 1981)
inline constexpr int kMinBandSidePx = 8;

// Pyramid levels for a w x h image: level l exists while min(w, h) >> (l + 1) >= 4.
inline int level_count(int w, int h) {
  int levels = 0;
  while ((std::min(w, h) >> (levels + 1)) >= kMinBandSidePx / 2) ++levels;
  return levels;
}

// Eccentricity (deg) of a point dist_px from the gaze: thesis eq. 1, e = atan(d / D), unscaled.
inline double ecc_of_distance(double dist_px, double view_distance_px) {
  return std::atan(dist_px / view_distance_px) * kDegPerRad;
}

// Local pixels per degree at eccentricity e on the project's flat screen around the gaze:
// geometric mean of radial D / cos^2 e and tangential D / cos e (per radian).
inline double local_ppd(double ppd_centre, double ecc_deg) {
  return ppd_centre / std::pow(std::cos(ecc_deg / kDegPerRad), 1.5);
}

// Bilinear lookup of a table over (log luminance, eccentricity).
inline float lookup(const std::vector<float>& table, double log_lum, double ecc_deg, const PerceptualMetric::TableGrid& g) {
  const int kLumSteps = g.lum_steps;
  const double u = std::clamp((log_lum - g.log_lum_min) / kLogLumStep, 0.0, double(kLumSteps - 1) - 1e-6);
  const double v = std::clamp(ecc_deg / kEccStepDeg, 0.0, double(g.ecc_steps - 1) - 1e-6);
  const int l = int(u), e = int(v);
  const double fu = u - l, fv = v - e;
  const auto at = [&](int ee, int ll) { return double(table[std::size_t(ee * kLumSteps + ll)]); };
  return float((1 - fv) * ((1 - fu) * at(e, l) + fu * at(e, l + 1)) + fv * ((1 - fu) * at(e + 1, l) + fu * at(e + 1, l + 1)));
}

// castleCSF's blend of the fields: alpha = min(1, |vis_field - 180| / 90) for a pixel offset (dx, dy).
inline double temporal_weight(double dx, double dy, Eye eye) {
  const double right_dx = eye == Eye::kRight ? dx : -dx;  // polar angles are the right eye's
  if (right_dx >= 0.0) return 1.0;
  return std::min(1.0, std::atan2(std::abs(dy), -right_dx) * kDegPerRad / 90.0);
}

inline void for_rows(foveation::Executor* ex, int rows, const std::function<void(int, int)>& body) {
  if (ex == nullptr || rows < 16) return body(0, rows);
  ex->parallel_chunks(std::size_t(rows), 8, [&](std::size_t a, std::size_t b, unsigned) { body(int(a), int(b)); });
}

}  // namespace foveart::eval::perceptual_detail

namespace foveart::eval {

// What depends on the gaze, the image size and the display alone (perceptual_evaluate.cpp), per
// pyramid level: each pixel's table row (eccentricity / kEccStepDeg, clamped to the table) and its
// temporal field's weight; the ring (metrics::kRingEdgesDeg) of every full-resolution pixel.
struct GazeTables {
  glm::vec2 gaze_px{};
  int width_px = 0, height_px = 0, levels = 0;
  std::vector<Plane> ecc_row, temporal_weight;
  std::vector<std::uint8_t> ring;
};

// The last gaze's tables, shared by copies of a metric (they share its display).
struct PerceptualMetric::GazeCache {
  std::mutex mutex;
  std::shared_ptr<const GazeTables> last;
};

}  // namespace foveart::eval
