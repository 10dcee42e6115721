// PSNR, SSIM (Wang, Bovik, Sheikh, Simoncelli 2004, "Image quality assessment:
// from error visibility to structural similarity") and their pooling per
// eccentricity ring.
#include <metrics/image_metrics.hpp>

#include <metrics/csf_error.hpp>
#include "foveation/eye_rays.hpp"
#include "foveation/srgb.hpp"

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace foveart::metrics {

namespace {

void check_sizes(const foveation::ImageRgb& a, const foveation::ImageRgb& b, const char* what) {
  if (a.width_px != b.width_px || a.height_px != b.height_px || a.rgb.size() != b.rgb.size() ||
      a.rgb.size() != a.pixel_count() * 3) {
    throw std::invalid_argument(std::string(what) + ": images of different size (" + std::to_string(a.width_px) + "x" +
                                std::to_string(a.height_px) + " vs " + std::to_string(b.width_px) + "x" +
                                std::to_string(b.height_px) + ")");
  }
}

// Rec. 601 luma.
std::vector<double> luma(const foveation::ImageRgb& im) {
  std::vector<double> y(im.pixel_count());
  for (std::size_t i = 0; i < y.size(); ++i) {
    const float* c = im.rgb.data() + i * 3;
    y[i] = rec601_luma(double(c[0]), double(c[1]), double(c[2]));
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

double psnr(const foveation::ImageRgb& ref, const foveation::ImageRgb& im, double peak) {
  check_sizes(ref, im, "psnr");
  double se = 0.0;
  for (std::size_t i = 0; i < ref.rgb.size(); ++i) {
    const double d = double(ref.rgb[i]) - double(im.rgb[i]);
    se += d * d;
  }
  return psnr_of_mse(ref.rgb.empty() ? 0.0 : se / double(ref.rgb.size()), peak);
}

std::vector<float> ssim_map(const foveation::ImageRgb& ref, const foveation::ImageRgb& im, double peak) {
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

double ssim(const foveation::ImageRgb& ref, const foveation::ImageRgb& im, double peak) {
  const auto map = ssim_map(ref, im, peak);
  double s = 0.0;
  for (float v : map) s += double(v);
  return map.empty() ? 1.0 : s / double(map.size());
}

double psnr_of_mse(double mse, double peak) {
  return mse > 0.0 ? 10.0 * std::log10(peak * peak / mse) : std::numeric_limits<double>::infinity();
}

foveation::ImageRgb display_encode(const foveation::ImageRgb& linear, float exposure) {
  foveation::ImageRgb out = linear;
  for (float& v : out.rgb) v = foveation::linear_to_srgb(std::clamp(std::isnan(v) ? 0.0f : v * exposure, 0.0f, 1.0f));
  return out;
}

EccentricityMap eccentricity_map(const FoveartEyeView& view, glm::vec2 gaze_px) {
  EccentricityMap m;
  m.width_px = int(view.width_px);
  m.height_px = int(view.height_px);
  m.gaze_px = gaze_px;
  const std::size_t n = std::size_t(m.width_px) * std::size_t(m.height_px);
  m.eccentricity_deg.resize(n);
  m.pixels_per_deg.resize(n);
  m.ring.resize(n);
  const foveation::EyeFrustum f = foveation::eye_frustum(view);
  const glm::dvec3 g = glm::normalize(glm::dvec3(foveation::view_direction_unnormalised(f, gaze_px)));
  const auto dir = [&f](double x, double y) {
    return glm::normalize(glm::dvec3(foveation::view_direction_unnormalised(f, glm::vec2(float(x), float(y)))));
  };
  const auto angle_deg = [](glm::dvec3 a, glm::dvec3 b) {
    // atan2(|a x b|, a.b): accurate for small angles, where acos is not.
    return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b)) * 180.0 / std::numbers::pi;
  };
  for (int y = 0; y < m.height_px; ++y) {
    for (int x = 0; x < m.width_px; ++x) {
      const std::size_t i = std::size_t(y) * std::size_t(m.width_px) + std::size_t(x);
      const glm::dvec3 d = dir(x + 0.5, y + 0.5);
      const double e = angle_deg(d, g);
      m.eccentricity_deg[i] = float(e);
      m.pixels_per_deg[i] = float(1.0 / std::max(1e-9, angle_deg(dir(x, y + 0.5), dir(x + 1.0, y + 0.5))));
      std::size_t r = 0;
      while (r + 1 < kRingCount && e >= kRingEdgesDeg[r + 1]) ++r;
      m.ring[i] = std::uint8_t(r);
      ++m.ring_pixels[r];
    }
  }
  return m;
}

namespace {

void check_map(const foveation::ImageRgb& ref, const foveation::ImageRgb& im, const EccentricityMap& map, const char* what) {
  check_sizes(ref, im, what);
  if (ref.width_px != map.width_px || ref.height_px != map.height_px) {
    throw std::invalid_argument(std::string(what) + ": image " + std::to_string(ref.width_px) + "x" +
                                std::to_string(ref.height_px) + " does not match the eccentricity map " +
                                std::to_string(map.width_px) + "x" + std::to_string(map.height_px));
  }
}

}  // namespace

std::array<double, kRingCount> ring_mse(const foveation::ImageRgb& ref, const foveation::ImageRgb& im, const EccentricityMap& map) {
  check_map(ref, im, map, "ring_mse");
  std::array<double, kRingCount> se{};
  for (std::size_t i = 0; i < map.ring.size(); ++i) {
    double s = 0.0;
    for (std::size_t c = 0; c < 3; ++c) {
      const double d = double(ref.rgb[i * 3 + c]) - double(im.rgb[i * 3 + c]);
      s += d * d;
    }
    se[map.ring[i]] += s;
  }
  for (std::size_t r = 0; r < kRingCount; ++r)
    se[r] = map.ring_pixels[r] ? se[r] / double(map.ring_pixels[r] * 3) : std::numeric_limits<double>::quiet_NaN();
  return se;
}

ImageComparison compare_images(const foveation::ImageRgb& ref, const foveation::ImageRgb& im, const EccentricityMap& map) {
  check_map(ref, im, map, "compare_images");
  ImageComparison out;
  const auto mse = ring_mse(ref, im, map);
  const auto ssim_px = ssim_map(ref, im);
  const auto csf_px = csf_error_map(ref, im, map);
  std::array<double, kRingCount> ss{}, cs{};
  double ss_all = 0.0, cs_all = 0.0, se_all = 0.0;
  for (std::size_t i = 0; i < map.ring.size(); ++i) {
    ss[map.ring[i]] += double(ssim_px[i]);
    cs[map.ring[i]] += double(csf_px[i]) * double(csf_px[i]);
  }
  const double n = double(map.ring.size());
  for (std::size_t r = 0; r < kRingCount; ++r) {
    RingMetrics rm;
    rm.from_deg = kRingEdgesDeg[r];
    rm.to_deg = kRingEdgesDeg[r + 1];
    rm.pixels = map.ring_pixels[r];
    ss_all += ss[r];
    cs_all += cs[r];
    if (rm.pixels == 0) {
      rm.mse = rm.psnr = rm.ssim = rm.csf_rmse = rm.csf_psnr = std::numeric_limits<double>::quiet_NaN();
    } else {
      se_all += mse[r] * double(rm.pixels);
      rm.mse = mse[r];
      rm.psnr = psnr_of_mse(mse[r], 1.0);
      rm.ssim = ss[r] / double(rm.pixels);
      const double cms = cs[r] / double(rm.pixels);
      rm.csf_rmse = std::sqrt(cms);
      rm.csf_psnr = psnr_of_mse(cms, 1.0);
    }
    out.rings.push_back(rm);
  }
  out.psnr = n > 0 ? psnr_of_mse(se_all / n, 1.0) : std::numeric_limits<double>::quiet_NaN();
  out.ssim = n > 0 ? ss_all / n : 1.0;
  out.csf_rmse = n > 0 ? std::sqrt(cs_all / n) : 0.0;
  return out;
}

std::array<double, kRingCount> ring_flicker(const std::vector<foveation::ImageRgb>& frames, const EccentricityMap& map) {
  std::array<double, kRingCount> out{};
  if (frames.size() < 2) return out;
  for (std::size_t t = 1; t < frames.size(); ++t) {
    const auto m = ring_mse(frames[t - 1], frames[t], map);
    for (std::size_t r = 0; r < kRingCount; ++r) out[r] += std::isnan(m[r]) ? 0.0 : m[r];
  }
  for (double& v : out) v = std::sqrt(v / double(frames.size() - 1));
  return out;
}

double mean_abs_difference(const foveation::ImageRgb& a, const foveation::ImageRgb& b) {
  check_sizes(a, b, "mean_abs_difference");
  double s = 0.0;
  for (std::size_t i = 0; i < a.rgb.size(); ++i) s += std::abs(double(a.rgb[i]) - double(b.rgb[i]));
  return a.rgb.empty() ? 0.0 : s / double(a.rgb.size());
}

}  // namespace foveart::metrics
