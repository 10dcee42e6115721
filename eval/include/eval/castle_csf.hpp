// Contrast sensitivity of the castleCSF model (Ashraf, Mantiuk, Chapiro & Wuerger 2024,
// "castleCSF - A contrast sensitivity function of color, area, spatiotemporal frequency,
// luminance and eccentricity", JoV 24(4):5; parameters of its release v0.2, the version
// of the paper) for a luminance modulation of a D65 background, static (the stimulus the
// perceptual metric sees, docs/lab/perceptual_metric.md) or flickering at one frequency.
//
// The achromatic mechanism is stelaCSF's (Mantiuk, Ashraf & Chapiro 2022, ACM TOG
// 41(4):145): a truncated log-parabola whose peak and peak frequency depend on
// luminance, Rovamo et al.'s (1993) area summation with a critical area A_c(rho), and
// the window of visibility's drop with eccentricity, 10^(-(a + b rho) e) (FovVideoVDP,
// Mantiuk et al. 2021), and its sustained and transient temporal channels: a flicker of
// omega Hz weights the sustained channel by exp(-omega^beta / sigma) and the transient one
// by a log-Gaussian around a peak frequency that rises with luminance (stelaCSF eqs. 5-6;
// the chromatic mechanisms have sustained channels only). A luminance modulation of D65 also
// drives castleCSF's red-green and yellow-violet mechanisms a little; their responses add as
// castleCSF's Minkowski sum (beta = 2), so that this is castleCSF's prediction for such a stimulus.
#pragma once

namespace foveart::eval {

// One stimulus, in the castleCSF data's terms.
struct CsfStimulus {
  double freq_cpd = 1.0;            // spatial frequency, cycles per degree
  double luminance_cd_m2 = 100.0;   // background (adapting) luminance
  double area_deg2 = 1.0;           // Gabor: pi ge_sigma^2; very large: an unbounded grating
  double ecc_deg = 0.0;             // eccentricity
  double vis_field_deg = 180.0;     // polar angle in the right eye's visual field: 0 temporal, 90 up, 180 nasal
  double temporal_freq_hz = 0.0;    // the modulation's flicker frequency; 0: static
};

// Whether the eccentricity term applies (kOff: the control that must fail off the fovea).
enum class EccentricityTerm : bool { kOff = false, kOn = true };

// castleCSF sensitivity (1 / threshold Michelson contrast) of a Gabor patch: achromatic
// stelaCSF channel plus the chromatic mechanisms' share (castleCSF eqs. for S_A, S_R, S_Y).
[[nodiscard]] double castle_sensitivity(const CsfStimulus& s, EccentricityTerm ecc = EccentricityTerm::kOn);

// The same in its two parts, whose Minkowski (beta = 2) sum it is: the achromatic mechanism
// (sustained + transient) and the chromatic mechanisms' share (red-green, yellow-violet).
struct CsfParts {
  double achromatic = 0.0;
  double chromatic = 0.0;
};
[[nodiscard]] CsfParts castle_sensitivity_parts(const CsfStimulus& s, EccentricityTerm ecc = EccentricityTerm::kOn);

// The critical area A_c(rho) of the achromatic sustained channel in deg^2 (Rovamo et al.
// 1993 after eq. 25; stelaCSF eq. 11): the area over which contrast energy sums. For a flicker
// (temporal_freq_hz > 0) at that background luminance, the critical area of the channel that
// sees it: the transient's where its response to a large stimulus exceeds the sustained's.
[[nodiscard]] double castle_critical_area_deg2(double freq_cpd, double temporal_freq_hz = 0.0,
                                               double luminance_cd_m2 = 100.0);
// The chromatic mechanisms' critical area (yellow-violet's A_0 / (1 + (rho / f_0)^2), deg^2; the
// red-green one is within 20 % of it above 0.2 cpd): where the chromatic share sums.
[[nodiscard]] double castle_chromatic_critical_area_deg2(double freq_cpd);

// Sensitivity to a uniform disc of radius_deg (castleCSF's disc model, Ashraf et al.
// 2024 sec. "Discs"): the most sensitive Gabor of a fixed area, scaled by radius^(1/beta).
[[nodiscard]] double castle_disc_sensitivity(double radius_deg, double luminance_cd_m2, double ecc_deg,
                                             double vis_field_deg, EccentricityTerm ecc = EccentricityTerm::kOn);

}  // namespace foveart::eval
