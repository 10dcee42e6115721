// Error of a reconstruction against a reference: PSNR, SSIM (Wang et al. 2004,
// on luma with 8x8 box windows, C1 = (0.01 L)^2, C2 = (0.03 L)^2), the same per
// eccentricity ring around the gaze, and the flicker of a sequence.
#pragma once

#include <limits>
#include <vector>

#include <glm/vec2.hpp>

#include "foveation/image.hpp"

namespace foveart::foveation {

// 10 log10(peak^2 / MSE) over all channels; +inf for identical images. Throws
// std::invalid_argument when the sizes differ.
double psnr(const ImageRgb& reference, const ImageRgb& image, double peak = 1.0);
// Mean SSIM over every pixel's window (the map of ssim_map()).
double ssim(const ImageRgb& reference, const ImageRgb& image, double peak = 1.0);
// Per-pixel SSIM of the 8x8 window around each pixel (clamped at the borders).
std::vector<float> ssim_map(const ImageRgb& reference, const ImageRgb& image, double peak = 1.0);

struct RingMetrics {
  double from_deg = 0.0;
  double to_deg = std::numeric_limits<double>::infinity();
  std::size_t pixels = 0;
  double psnr = 0.0;
  double ssim = 0.0;
};

// Rings 0-5, 5-10, 10-20, 20-30 and beyond 30 degrees of eccentricity
// atan(d / view_distance_px) from the gaze (thesis eq. 1 without scaling).
std::vector<RingMetrics> ring_metrics(const ImageRgb& reference, const ImageRgb& image, glm::vec2 gaze_px,
                                      double view_distance_px, double peak = 1.0);

// Flicker: mean |I(t) - I(t-1)| over pixels and channels (TAA's temporal stability).
double mean_abs_difference(const ImageRgb& a, const ImageRgb& b);

}  // namespace foveart::foveation
