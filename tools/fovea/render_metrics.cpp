// PSNR and SSIM (Wang et al. 2004, "Image quality assessment: from error
// visibility to structural similarity"), constants K1 = 0.01, K2 = 0.03, L = 1.
#include "render_metrics.hpp"

#include <foveation/eye_rays.hpp>
#include <foveation/srgb.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace foveart::tools {
namespace {

// Display value of a linear colour, the PSNR/SSIM domain (clamped to [0, 1]).
float encode(float linear) { return foveation::linear_to_srgb(std::clamp(linear, 0.0f, 1.0f)); }

double psnr_from_mse(double mse) {
  return mse <= 0.0 ? std::numeric_limits<double>::infinity() : 10.0 * std::log10(1.0 / mse);
}

constexpr int kWindow = 8;

}  // namespace

ImageComparison compare_images(const foveation::ImageRgb& test, const foveation::ImageRgb& ref,
                               const FoveartEyeView& view, glm::vec2 gaze_px,
                               const std::vector<double>& edges) {
  ImageComparison out;
  const uint32_t w = static_cast<uint32_t>(ref.width_px), h = static_cast<uint32_t>(ref.height_px);
  if (test.width_px != ref.width_px || test.height_px != ref.height_px || ref.rgb.size() != ref.pixel_count() * 3 ||
      test.rgb.size() != ref.rgb.size())
    return out;
  const size_t n = ref.pixel_count();
  std::vector<double> la(n), lb(n);
  std::vector<double> sq(n);
  for (size_t i = 0; i < n; ++i) {
    double s = 0.0;
    float ya = 0.0f, yb = 0.0f;
    for (int c = 0; c < 3; ++c) {
      const float a = encode(test.rgb[3 * i + static_cast<size_t>(c)]);
      const float b = encode(ref.rgb[3 * i + static_cast<size_t>(c)]);
      s += static_cast<double>(a - b) * static_cast<double>(a - b);
      const float wgt = c == 0 ? 0.2126f : (c == 1 ? 0.7152f : 0.0722f);
      ya += wgt * a;
      yb += wgt * b;
    }
    sq[i] = s / 3.0;
    la[i] = static_cast<double>(ya);
    lb[i] = static_cast<double>(yb);
  }
  // Eccentricity of each pixel: angle between its ray and the gaze ray.
  const foveation::EyeFrustum f = foveation::eye_frustum(view);
  const foveation::EyeFrustum* fp = &f;
  const glm::vec3 g = glm::normalize(foveation::view_direction_unnormalised(f, gaze_px));
  auto ecc_deg = [fp, g](float x, float y) {
    const glm::vec3 d = glm::normalize(foveation::view_direction_unnormalised(*fp, glm::vec2(x, y)));
    return static_cast<double>(std::acos(std::clamp(glm::dot(d, g), -1.0f, 1.0f))) * 180.0 / 3.14159265358979;
  };
  const size_t nrings = edges.size() > 1 ? edges.size() - 1 : 0;
  auto ring_of = [&](double e) -> int {
    for (size_t r = 0; r < nrings; ++r)
      if (e >= edges[r] && e < edges[r + 1]) return static_cast<int>(r);
    return -1;
  };
  std::vector<double> ring_sq(nrings, 0.0), ring_ssim(nrings, 0.0);
  std::vector<uint64_t> ring_px(nrings, 0), ring_win(nrings, 0);
  double total_sq = 0.0;
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x) {
      const size_t i = static_cast<size_t>(y) * w + x;
      total_sq += sq[i];
      const int r = ring_of(ecc_deg(static_cast<float>(x) + 0.5f, static_cast<float>(y) + 0.5f));
      if (r >= 0) {
        ring_sq[r] += sq[i];
        ++ring_px[r];
      }
    }
  out.psnr = psnr_from_mse(total_sq / static_cast<double>(n));

  const double c1 = 0.01 * 0.01, c2 = 0.03 * 0.03;
  double ssim_sum = 0.0;
  uint64_t windows = 0;
  for (uint32_t y0 = 0; y0 + kWindow <= h; y0 += kWindow / 2)
    for (uint32_t x0 = 0; x0 + kWindow <= w; x0 += kWindow / 2) {
      double ma = 0, mb = 0, va = 0, vb = 0, cov = 0;
      for (int dy = 0; dy < kWindow; ++dy)
        for (int dx = 0; dx < kWindow; ++dx) {
          const size_t i = static_cast<size_t>(y0 + dy) * w + x0 + dx;
          ma += la[i];
          mb += lb[i];
        }
      const double m = kWindow * kWindow;
      ma /= m;
      mb /= m;
      for (int dy = 0; dy < kWindow; ++dy)
        for (int dx = 0; dx < kWindow; ++dx) {
          const size_t i = static_cast<size_t>(y0 + dy) * w + x0 + dx;
          const double da = la[i] - ma, db = lb[i] - mb;
          va += da * da;
          vb += db * db;
          cov += da * db;
        }
      va /= m - 1;
      vb /= m - 1;
      cov /= m - 1;
      const double s = ((2 * ma * mb + c1) * (2 * cov + c2)) / ((ma * ma + mb * mb + c1) * (va + vb + c2));
      ssim_sum += s;
      ++windows;
      const int r = ring_of(ecc_deg(static_cast<float>(x0) + kWindow / 2.0f, static_cast<float>(y0) + kWindow / 2.0f));
      if (r >= 0) {
        ring_ssim[r] += s;
        ++ring_win[r];
      }
    }
  out.ssim = windows ? ssim_sum / static_cast<double>(windows) : 1.0;
  for (size_t r = 0; r < nrings; ++r) {
    if (ring_px[r] == 0) continue;
    RingMetrics rm;
    rm.from_deg = edges[r];
    rm.to_deg = edges[r + 1];
    rm.pixels = ring_px[r];
    rm.psnr = psnr_from_mse(ring_sq[r] / static_cast<double>(ring_px[r]));
    rm.ssim = ring_win[r] ? ring_ssim[r] / static_cast<double>(ring_win[r]) : 1.0;
    out.rings.push_back(rm);
  }
  return out;
}

}  // namespace foveart::tools
