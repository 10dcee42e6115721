#include "foveation/image_metrics.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace foveart::foveation {

namespace {

void check_sizes(const ImageRgb& a, const ImageRgb& b, const char* what) {
  if (a.width_px != b.width_px || a.height_px != b.height_px || a.rgb.size() != b.rgb.size() ||
      a.rgb.size() != a.pixel_count() * 3) {
    throw std::invalid_argument(std::string(what) + ": images of different size (" + std::to_string(a.width_px) + "x" +
                                std::to_string(a.height_px) + " vs " + std::to_string(b.width_px) + "x" +
                                std::to_string(b.height_px) + ")");
  }
}

double psnr_of(double mse, double peak) {
  return mse > 0.0 ? 10.0 * std::log10(peak * peak / mse) : std::numeric_limits<double>::infinity();
}

// Rec. 601 luma.
std::vector<double> luma(const ImageRgb& im) {
  std::vector<double> y(im.pixel_count());
  for (std::size_t i = 0; i < y.size(); ++i) {
    const float* c = im.rgb.data() + i * 3;
    y[i] = 0.299 * double(c[0]) + 0.587 * double(c[1]) + 0.114 * double(c[2]);
  }
  return y;
}

// Summed-area table with a zero first row/column: (w + 1) x (h + 1).
std::vector<double> integral(const std::vector<double>& v, int w, int h) {
  std::vector<double> s(std::size_t(w + 1) * std::size_t(h + 1), 0.0);
  for (int y = 0; y < h; ++y) {
    double row = 0.0;
    for (int x = 0; x < w; ++x) {
      row += v[std::size_t(y) * std::size_t(w) + std::size_t(x)];
      s[std::size_t(y + 1) * std::size_t(w + 1) + std::size_t(x + 1)] = s[std::size_t(y) * std::size_t(w + 1) + std::size_t(x + 1)] + row;
    }
  }
  return s;
}

double box(const std::vector<double>& s, int w, int x0, int y0, int x1, int y1) {
  const auto at = [&](int x, int y) { return s[std::size_t(y) * std::size_t(w + 1) + std::size_t(x)]; };
  return at(x1, y1) - at(x0, y1) - at(x1, y0) + at(x0, y0);
}

}  // namespace

double psnr(const ImageRgb& ref, const ImageRgb& im, double peak) {
  check_sizes(ref, im, "psnr");
  double se = 0.0;
  for (std::size_t i = 0; i < ref.rgb.size(); ++i) {
    const double d = double(ref.rgb[i]) - double(im.rgb[i]);
    se += d * d;
  }
  return psnr_of(ref.rgb.empty() ? 0.0 : se / double(ref.rgb.size()), peak);
}

std::vector<float> ssim_map(const ImageRgb& ref, const ImageRgb& im, double peak) {
  check_sizes(ref, im, "ssim");
  const int w = ref.width_px, h = ref.height_px;
  const auto a = luma(ref), b = luma(im);
  std::vector<double> aa(a.size()), bb(a.size()), ab(a.size());
  for (std::size_t i = 0; i < a.size(); ++i) aa[i] = a[i] * a[i], bb[i] = b[i] * b[i], ab[i] = a[i] * b[i];
  const auto sa = integral(a, w, h), sb = integral(b, w, h), saa = integral(aa, w, h), sbb = integral(bb, w, h),
             sab = integral(ab, w, h);
  const double c1 = (0.01 * peak) * (0.01 * peak), c2 = (0.03 * peak) * (0.03 * peak);
  std::vector<float> map(a.size());
  for (int y = 0; y < h; ++y) {
    const int y0 = std::max(0, y - 4), y1 = std::min(h, y + 4);
    for (int x = 0; x < w; ++x) {
      const int x0 = std::max(0, x - 4), x1 = std::min(w, x + 4);
      const double n = double((x1 - x0) * (y1 - y0));
      const double ma = box(sa, w, x0, y0, x1, y1) / n, mb = box(sb, w, x0, y0, x1, y1) / n;
      const double va = std::max(0.0, box(saa, w, x0, y0, x1, y1) / n - ma * ma);
      const double vb = std::max(0.0, box(sbb, w, x0, y0, x1, y1) / n - mb * mb);
      const double cov = box(sab, w, x0, y0, x1, y1) / n - ma * mb;
      map[std::size_t(y) * std::size_t(w) + std::size_t(x)] =
          float(((2 * ma * mb + c1) * (2 * cov + c2)) / ((ma * ma + mb * mb + c1) * (va + vb + c2)));
    }
  }
  return map;
}

double ssim(const ImageRgb& ref, const ImageRgb& im, double peak) {
  const auto map = ssim_map(ref, im, peak);
  double s = 0.0;
  for (float v : map) s += double(v);
  return map.empty() ? 1.0 : s / double(map.size());
}

std::vector<RingMetrics> ring_metrics(const ImageRgb& ref, const ImageRgb& im, glm::vec2 gaze_px,
                                      double view_distance_px, double peak) {
  check_sizes(ref, im, "ring metrics");
  if (!(view_distance_px > 0.0) || !std::isfinite(view_distance_px)) {
    throw std::invalid_argument("ring metrics: view distance must be positive and finite");
  }
  std::vector<RingMetrics> rings = {{0, 5}, {5, 10}, {10, 20}, {20, 30}, {30, std::numeric_limits<double>::infinity()}};
  const auto map = ssim_map(ref, im, peak);
  std::vector<double> se(rings.size(), 0.0), ss(rings.size(), 0.0);
  for (int y = 0; y < ref.height_px; ++y) {
    for (int x = 0; x < ref.width_px; ++x) {
      const double dx = x + 0.5 - double(gaze_px.x), dy = y + 0.5 - double(gaze_px.y);
      const double ecc = std::atan(std::hypot(dx, dy) / view_distance_px) * 180.0 / std::numbers::pi;
      std::size_t r = 0;
      while (r + 1 < rings.size() && ecc >= rings[r].to_deg) ++r;
      const std::size_t i = std::size_t(y) * std::size_t(ref.width_px) + std::size_t(x);
      for (int c = 0; c < 3; ++c) {
        const double d = double(ref.rgb[i * 3 + std::size_t(c)]) - double(im.rgb[i * 3 + std::size_t(c)]);
        se[r] += d * d;
      }
      ss[r] += double(map[i]);
      ++rings[r].pixels;
    }
  }
  for (std::size_t r = 0; r < rings.size(); ++r) {
    if (rings[r].pixels == 0) {
      rings[r].psnr = std::numeric_limits<double>::quiet_NaN();
      rings[r].ssim = std::numeric_limits<double>::quiet_NaN();
      continue;
    }
    rings[r].psnr = psnr_of(se[r] / double(rings[r].pixels * 3), peak);
    rings[r].ssim = ss[r] / double(rings[r].pixels);
  }
  return rings;
}

double mean_abs_difference(const ImageRgb& a, const ImageRgb& b) {
  check_sizes(a, b, "mean_abs_difference");
  double s = 0.0;
  for (std::size_t i = 0; i < a.rgb.size(); ++i) s += std::abs(double(a.rgb[i]) - double(b.rgb[i]));
  return a.rgb.empty() ? 0.0 : s / double(a.rgb.size());
}

}  // namespace foveart::foveation
