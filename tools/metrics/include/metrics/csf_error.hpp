// A perceptual, eccentricity-aware error: the luma difference split into
// octave bands, each band weighted by the foveated contrast sensitivity of the
// thesis's model (eqs. 1-3; Geisler & Perry 1998 as used by Wang et al. 2001,
// "Embedded foveation image coding", IEEE TIP 10(10), eq. 5):
//   S(f, e) / S(f, 0) = exp(-alpha f e / e2)   for f <= f_m = min(f_c(e), f_d),
//                     = 0                      beyond,
// with f_c(e) = e2 ln(1/CT0) / ((e + e2) alpha) (eq. 2), f_d the display's
// Nyquist frequency (eq. 3, here per pixel: half the local pixels per degree),
// CT0 = 1/64, alpha = 0.106, e2 = 2.3.
//
// Bands: B_1 = d - G_1, B_l = G_{l-1} - G_l (l = 2..5), L = G_5, where d is the
// display-luma difference (Rec. 601 weights) and G_l is d blurred twice with a
// box of radius 2^(l-1) px; band l has the centre frequency ppd * 2^-l
// cycles/degree (Wang et al. 2001's wavelet levels), the low-pass L ppd * 2^-6.
// The weighted error of a pixel is |sum_l w_l B_l + w_L L|: where every weight
// is 1 (the gaze point, frequencies the eye resolves there) the bands telescope
// back to |d|, the plain luma error; away from the gaze the fine bands fade.
#pragma once

#include <vector>

#include "foveation/image.hpp"
#include <metrics/image_metrics.hpp>

namespace foveart::metrics {

// Foveated contrast sensitivity relative to the fovea's, S(f, e) / S(f, 0)
// (Wang et al. 2001 eq. 5 with thesis eqs. 2-3): 0 beyond the cut-off.
double csf_weight(double frequency_cpd, double eccentricity_deg, double pixels_per_deg);

// Per pixel |sum_l w_l B_l + w_L L| of a display-luma difference d (one value per pixel of the map):
// the weighting itself, for a difference that is already luma.
// Throws std::invalid_argument when the sizes differ or the map lacks its eccentricities.
std::vector<float> csf_weighted_luma(const std::vector<double>& luma_difference, const EccentricityMap& map);

// Per pixel weighted error of `image` against `reference` (display values, same size as the map):
// csf_weighted_luma of their luma difference.
// With the weights uniform over an image its gain lies in [0, 1] at every frequency (the weights
// grow towards the coarse bands, and each double box blur's gain lies in [0, 1]).
// Throws std::invalid_argument when the sizes differ or the map lacks its eccentricities.
std::vector<float> csf_error_map(const foveation::ImageRgb& reference, const foveation::ImageRgb& image, const EccentricityMap& map);

}  // namespace foveart::metrics
