// CSF-weighted error (csf_error.hpp): Wang, Lu & Bovik 2001 eq. 5 with the
// thesis's eqs. 1-3, over a band split of the display-luma difference.
#include <metrics/csf_error.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>

namespace foveart::metrics {
namespace {

// Geisler & Perry 1998 fit, as the thesis and Wang et al. 2001 use it.
constexpr double kCt0 = 1.0 / 64.0;
constexpr double kAlpha = 0.106;
constexpr double kE2Deg = 2.3;
constexpr int kBands = 5;

// Box blur of radius r along rows then columns (clamped window at the borders), via running sums.
void box_blur(const std::vector<double>& in, std::vector<double>& out, int w, int h, int r) {
  std::vector<double> tmp(in.size());
  std::vector<double> line;
  for (int y = 0; y < h; ++y) {
    line.assign(std::size_t(w) + 1, 0.0);
    const double* row = in.data() + std::size_t(y) * std::size_t(w);
    for (int x = 0; x < w; ++x) line[std::size_t(x) + 1] = line[std::size_t(x)] + row[x];
    for (int x = 0; x < w; ++x) {
      const int x0 = std::max(0, x - r), x1 = std::min(w, x + r + 1);
      tmp[std::size_t(y) * std::size_t(w) + std::size_t(x)] = (line[std::size_t(x1)] - line[std::size_t(x0)]) / double(x1 - x0);
    }
  }
  out.resize(in.size());
  for (int x = 0; x < w; ++x) {
    line.assign(std::size_t(h) + 1, 0.0);
    for (int y = 0; y < h; ++y) line[std::size_t(y) + 1] = line[std::size_t(y)] + tmp[std::size_t(y) * std::size_t(w) + std::size_t(x)];
    for (int y = 0; y < h; ++y) {
      const int y0 = std::max(0, y - r), y1 = std::min(h, y + r + 1);
      out[std::size_t(y) * std::size_t(w) + std::size_t(x)] = (line[std::size_t(y1)] - line[std::size_t(y0)]) / double(y1 - y0);
    }
  }
}

}  // namespace

// Wang et al. 2001 eq. 5: S(f, e) / S(f, 0) = exp(-alpha f e / e2) below f_m = min(f_c(e), f_d) (thesis eqs. 2, 3).
double csf_weight(double frequency_cpd, double eccentricity_deg, double pixels_per_deg) {
  const double e = std::max(0.0, eccentricity_deg);
  const double f_c = kE2Deg * std::log(1.0 / kCt0) / ((e + kE2Deg) * kAlpha);  // eq. 2
  const double f_d = 0.5 * pixels_per_deg;                                     // eq. 3: pi N v / 360
  if (frequency_cpd > std::min(f_c, f_d) * (1.0 + 1e-9)) return 0.0;
  return std::exp(-kAlpha * frequency_cpd * e / kE2Deg);
}

std::vector<float> csf_weighted_luma(const std::vector<double>& luma_difference, const EccentricityMap& map) {
  const std::size_t n = std::size_t(std::max(map.width_px, 0)) * std::size_t(std::max(map.height_px, 0));
  if (luma_difference.size() != n || map.eccentricity_deg.size() != n || map.pixels_per_deg.size() != n) {
    throw std::invalid_argument("csf_weighted_luma: " + std::to_string(luma_difference.size()) +
                                " luma differences for an eccentricity map of " + std::to_string(map.width_px) + "x" +
                                std::to_string(map.height_px) + " (" + std::to_string(map.eccentricity_deg.size()) +
                                " eccentricities, " + std::to_string(map.pixels_per_deg.size()) +
                                " pixels per degree)");
  }
  const int w = map.width_px, h = map.height_px;
  const std::vector<double>& d = luma_difference;
  std::vector<double> sum(n, 0.0), prev = d, blurred, once;
  for (int l = 1; l <= kBands + 1; ++l) {
    const bool low_pass = l > kBands;
    if (!low_pass) {
      const int r = 1 << (l - 1);
      box_blur(d, once, w, h, r);
      box_blur(once, blurred, w, h, r);
    }
    for (std::size_t i = 0; i < n; ++i) {
      const double band = low_pass ? prev[i] : prev[i] - blurred[i];
      const double ppd = double(map.pixels_per_deg[i]);
      const double f_cpd = ppd * std::ldexp(1.0, -l);
      sum[i] += csf_weight(f_cpd, double(map.eccentricity_deg[i]), ppd) * band;
    }
    if (!low_pass) prev.swap(blurred);
  }
  std::vector<float> out(n);
  for (std::size_t i = 0; i < n; ++i) out[i] = float(std::abs(sum[i]));
  return out;
}

std::vector<float> csf_error_map(const foveation::ImageRgb& ref, const foveation::ImageRgb& im, const EccentricityMap& map) {
  // The images against each other and the map's size; csf_weighted_luma checks the map's own arrays.
  if (ref.width_px != im.width_px || ref.height_px != im.height_px || ref.rgb.size() != im.rgb.size() ||
      ref.width_px != map.width_px || ref.height_px != map.height_px || ref.rgb.size() != ref.pixel_count() * 3) {
    throw std::invalid_argument("csf_error_map: image " + std::to_string(im.width_px) + "x" +
                                std::to_string(im.height_px) + ", reference " + std::to_string(ref.width_px) + "x" +
                                std::to_string(ref.height_px) + " and eccentricity map " +
                                std::to_string(map.width_px) + "x" + std::to_string(map.height_px) + " differ");
  }
  std::vector<double> d(ref.pixel_count());
  for (std::size_t i = 0; i < d.size(); ++i) {
    const float* a = im.rgb.data() + i * 3;
    const float* b = ref.rgb.data() + i * 3;
    d[i] = rec601_luma(double(a[0]) - double(b[0]), double(a[1]) - double(b[1]), double(a[2]) - double(b[2]));
  }
  return csf_weighted_luma(d, map);
}

}  // namespace foveart::metrics
