// Error of an image against a reference: PSNR, SSIM (Wang et al. 2004, on luma
// with 8x8 box windows, C1 = (0.01 L)^2, C2 = (0.03 L)^2), a CSF-weighted
// error (csf_error.hpp), each overall and per eccentricity ring around the
// gaze, and the flicker of a sequence per ring. The one implementation every
// tool calls (`fovea render`, `fovea reconstruct`, and the lab's `fovea-eval`).
//
// Domain: the metrics compare the values they are given. Tools compare display
// values (display_encode: sRGB of the exposed linear colour clamped to [0, 1],
// no tone-mapping curve), so that PSNR and SSIM mean what they mean for an
// 8-bit image, without its rounding, and stay linear in radiance up to white.
// Errors: mismatched sizes throw std::invalid_argument naming the function.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <vector>

#include <glm/vec2.hpp>

#include "foveation/image.hpp"
#include "foveation/ray_trace.h"

namespace foveart::metrics {

// 10 log10(peak^2 / MSE) over all channels; +inf for identical images.
double psnr(const foveation::ImageRgb& reference, const foveation::ImageRgb& image, double peak = 1.0);
// Mean SSIM over every pixel's window (the map of ssim_map()).
double ssim(const foveation::ImageRgb& reference, const foveation::ImageRgb& image, double peak = 1.0);
// Per-pixel SSIM of the 8x8 window around each pixel (clamped at the borders).
std::vector<float> ssim_map(const foveation::ImageRgb& reference, const foveation::ImageRgb& image, double peak = 1.0);
// PSNR of a mean squared error: 10 log10(peak^2 / mse), +inf for 0.
double psnr_of_mse(double mse, double peak = 1.0);

// Rec. 601 luma of an RGB triple: the one luma of SSIM, the CSF-weighted error and the references.
inline double rec601_luma(double r, double g, double b) { return 0.299 * r + 0.587 * g + 0.114 * b; }

// Display values of a linear image: sRGB (IEC 61966-2-1) of exposure x each
// channel clamped to [0, 1] (the exposure of the run's display transform).
foveation::ImageRgb display_encode(const foveation::ImageRgb& linear, float exposure = 1.0f);

// Eccentricity ring edges in degrees: 0-2.5, 2.5-5, 5-10, 10-20, 20-30, 30-45, > 45.
inline constexpr std::array<double, 8> kRingEdgesDeg = {0.0, 2.5, 5.0, 10.0, 20.0, 30.0, 45.0,
                                                        std::numeric_limits<double>::infinity()};
inline constexpr std::size_t kRingCount = kRingEdgesDeg.size() - 1;

// Per pixel of a view: its eccentricity, the angle between the ray through the
// pixel centre and the gaze ray (thesis eq. 1 generalised to any frustum: for
// a symmetric pinhole and a centred gaze it is atan(d / (N v))), its ring and
// its local pixels per degree (horizontal neighbours' ray angle). Computed once
// per view and gaze and shared by every metric of that frame.
struct EccentricityMap {
  int width_px = 0;
  int height_px = 0;
  glm::vec2 gaze_px{};
  std::vector<float> eccentricity_deg;
  std::vector<float> pixels_per_deg;
  std::vector<std::uint8_t> ring;  // index into kRingEdgesDeg
  std::array<std::uint64_t, kRingCount> ring_pixels{};
};
EccentricityMap eccentricity_map(const FoveartEyeView& view, glm::vec2 gaze_px);

struct RingMetrics {
  double from_deg = 0.0;
  double to_deg = std::numeric_limits<double>::infinity();
  std::uint64_t pixels = 0;
  double mse = 0.0;        // over the ring's pixels and the 3 channels
  double psnr = 0.0;       // dB, peak 1; +inf when equal; NaN for an empty ring
  double ssim = 0.0;       // mean of ssim_map over the ring's pixels
  double csf_rmse = 0.0;   // root mean square of csf_error_map over the ring
  double csf_psnr = 0.0;   // 10 log10(1 / csf_rmse^2), dB
};

struct ImageComparison {
  double psnr = 0.0;
  double ssim = 0.0;
  double csf_rmse = 0.0;
  std::vector<RingMetrics> rings;  // kRingCount rings, empty ones included (pixels = 0)
};

// Every metric of `image` against `reference` (same size as the map), overall and per ring.
ImageComparison compare_images(const foveation::ImageRgb& reference, const foveation::ImageRgb& image, const EccentricityMap& map);

// Squared error per ring only (cheap): MSE per ring over 3 channels.
std::array<double, kRingCount> ring_mse(const foveation::ImageRgb& reference, const foveation::ImageRgb& image, const EccentricityMap& map);

// Flicker: mean |I(t) - I(t-1)| over pixels and channels (TAA's temporal stability).
double mean_abs_difference(const foveation::ImageRgb& a, const foveation::ImageRgb& b);

// Flicker per ring of a sequence: the root mean square over consecutive frame
// pairs, pixels and channels of I(t) - I(t-1). Zero for fewer than two frames.
std::array<double, kRingCount> ring_flicker(const std::vector<foveation::ImageRgb>& frames, const EccentricityMap& map);

}  // namespace foveart::metrics
