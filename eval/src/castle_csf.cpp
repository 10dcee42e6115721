// castleCSF for a D65 luminance modulation (castle_csf.hpp).
#include <eval/castle_csf.hpp>

#include <algorithm>
#include <cmath>
#include <complex>
#include <span>

namespace foveart::eval {
namespace {

// One mechanism's parameters (castleCSF v0.2 get_default_par, "ach"/"rg"/"yv").
struct Channel {
  std::span<const double> s_max;  // peak sensitivity against luminance (lum_dep family)
  std::span<const double> f_max;  // peak frequency against luminance
  double bw = 0.0;                // log-parabola bandwidth (log2)
  double trunc = 0.0;             // achromatic: flat at 1 - trunc below the peak; < 0: chromatic (flat at 1)
  double area0_deg2 = 0.0;        // Rovamo's A_0
  double f0_cpd = 0.0;            // Rovamo's f_0
  double sigma_sust = 0.0;        // sustained temporal response exp(-omega^beta / sigma); unused by the transient
  double beta_sust = 0.0;
};

constexpr double kSustSmax[] = {56.0639, 6.64673, 0.144809, 5.30245e-07, 8.71574e+09};
constexpr double kSustFmax[] = {1.78263, 66.992, 0.269402};
constexpr double kTransSmax[] = {0.193435, 2793.56};
constexpr double kTransFmax[] = {0.000326927};
constexpr double kRgSmax[] = {730.147, 38.2307, 0.469349};
constexpr double kRgFmax[] = {0.0169475};
constexpr double kYvSmax[] = {99.6752, 62.5513, 0.407922};
constexpr double kYvFmax[] = {0.00363324};

// Sustained A_0, f_0: Rovamo's 270 deg^2, 0.65 cpd, the values castleCSF's code evaluates (its fitted
// ach_sust.A_0 / f_0 are never copied into the achromatic object, whose defaults lack them).
constexpr Channel kSustained{kSustSmax, kSustFmax, 0.000212711, 0.282947, 270.0, 0.65, 10.467, 1.3314};
constexpr Channel kTransient{kTransSmax, kTransFmax, 2.67727, 0.000241177, 3.58559, 2.94741};
constexpr Channel kRedGreen{kRgSmax, kRgFmax, 2.46441, -1.0, 2879.13, 0.0704339, 16.541, 1.15549};
constexpr Channel kYellowViolet{kYvSmax, kYvFmax, 2.72495, -1.0, 2.85765e+07, 0.000648528, 7.9187, 0.999363};

// Eccentricity drop 10^(-(a + b rho) e), temporal (alpha = 1) and nasal (alpha = 0) field.
struct EccDrop {
  double a_temporal, a_nasal, b_temporal, b_nasal;
};
constexpr EccDrop kAchDrop{0.0259781, 0.0452708, 0.0217926, 0.0068348};
constexpr EccDrop kRgDrop{0.0591431, 2.89648e-05, 2.04986e-69, 0.180118};
constexpr EccDrop kYvDrop{0.00357397, 5.85804e-141, 0.0080878, 0.0147658};

// castleCSF's D65 background in LMS per cd/m^2 and its mechanism matrix (colmat of v0.2).
constexpr double kD65Lms[] = {0.6991, 0.3009, 0.0198};
constexpr double kRgM = 1.95127;
constexpr double kYvS = 86.9163;

// castleCSF CSF_base get_lum_dep: the luminance dependence family (1, 2, 3 or 5 parameters).
double lum_dep(std::span<const double> p, double lum) {
  switch (p.size()) {
    case 1: return p[0];
    case 2: return p[1] * std::pow(lum, p[0]);
    case 3: return p[0] * std::pow(1.0 + p[1] / lum, -p[2]);
    default: return p[0] * std::pow(1.0 + p[1] / lum, -p[2]) * (1.0 - std::pow(1.0 + p[3] / lum, -p[4]));
  }
}

// Rovamo et al. 1993 (stelaCSF eq. 11): a channel's critical area A_0 / (1 + (rho / f_0)^2), deg^2.
double critical_area_deg2(const Channel& c, double rho) {
  return c.area0_deg2 / (1.0 + (rho / c.f0_cpd) * (rho / c.f0_cpd));
}

// stelaCSF eqs. 8-11: truncated log-parabola times Rovamo's area summation, times rho.
double channel_sensitivity(const Channel& c, double rho, double area, double lum) {
  const double s_max = lum_dep(c.s_max, lum);
  const double f_max = lum_dep(c.f_max, lum);
  const double d = std::log10(rho) - std::log10(f_max);
  double lp = std::pow(10.0, -d * d / std::exp2(c.bw));
  if (rho < f_max) lp = c.trunc < 0.0 ? 1.0 : std::max(lp, 1.0 - c.trunc);
  const double ac = critical_area_deg2(c, rho);
  return s_max * lp * std::sqrt(ac / (1.0 + ac / area)) * rho;
}

// stelaCSF eq. 14 / FovVideoVDP eq. 5: 10^(-(a + b rho) e), a and b blended between the fields.
double ecc_factor(const EccDrop& d, double rho, const CsfStimulus& s) {
  const double alpha = std::min(1.0, std::abs(s.vis_field_deg - 180.0) / 90.0);
  const double a = alpha * d.a_temporal + (1.0 - alpha) * d.a_nasal;
  const double b = alpha * d.b_temporal + (1.0 - alpha) * d.b_nasal;
  return std::pow(10.0, -(a + b * rho) * s.ecc_deg);
}

// stelaCSF eq. 5: a mechanism's sustained response to a flicker of omega Hz, exp(-omega^beta / sigma).
double sustained_response(const Channel& c, double omega_hz) {
  return omega_hz > 0.0 ? std::exp(-std::pow(omega_hz, c.beta_sust) / c.sigma_sust) : 1.0;
}

// stelaCSF eq. 6: the transient channel's response exp(-|omega^beta - omega_0^beta|^2 / sigma), its peak
// omega_0 rising with log luminance. Below 0.011 cd/m^2 omega_0 < 0 and omega_0^beta is complex (the
// principal power, as castleCSF evaluates it): the channel fades at every frequency, as at night.
double transient_response(double omega_hz, double lum) {
  constexpr double kBeta = 0.1898, kSigma = 0.085424;
  const std::complex<double> omega0(std::log10(lum) * 2.36951 + 4.60295, 0.0);
  return std::exp(-std::norm(std::pow(omega_hz, kBeta) - std::pow(omega0, kBeta)) / kSigma);
}

}  // namespace

double castle_critical_area_deg2(double freq_cpd, double temporal_freq_hz, double luminance_cd_m2) {
  if (!(temporal_freq_hz > 0.0)) return critical_area_deg2(kSustained, freq_cpd);
  constexpr double kLargeDeg2 = 1e6;
  const double sustained = sustained_response(kSustained, temporal_freq_hz) *
                           channel_sensitivity(kSustained, freq_cpd, kLargeDeg2, luminance_cd_m2);
  const double transient = transient_response(temporal_freq_hz, luminance_cd_m2) *
                           channel_sensitivity(kTransient, freq_cpd, kLargeDeg2, luminance_cd_m2);
  return critical_area_deg2(transient > sustained ? kTransient : kSustained, freq_cpd);
}

double castle_chromatic_critical_area_deg2(double freq_cpd) {
  return critical_area_deg2(kYellowViolet, freq_cpd);
}

CsfParts castle_sensitivity_parts(const CsfStimulus& s, EccentricityTerm ecc) {
  const double rho = s.freq_cpd;
  const double lum = s.luminance_cd_m2;  // unclamped, as castleCSF evaluates it (the data reach 2e-5 cd/m^2)
  const double omega = s.temporal_freq_hz;
  const bool drop = ecc == EccentricityTerm::kOn;
  const double s_ach = (sustained_response(kSustained, omega) * channel_sensitivity(kSustained, rho, s.area_deg2, lum) +
                        transient_response(omega, lum) * channel_sensitivity(kTransient, rho, s.area_deg2, lum)) *
                       (drop ? ecc_factor(kAchDrop, rho, s) : 1.0);
  const double s_rg = sustained_response(kRedGreen, omega) * channel_sensitivity(kRedGreen, rho, s.area_deg2, lum) *
                      (drop ? ecc_factor(kRgDrop, rho, s) : 1.0);
  const double s_yv = sustained_response(kYellowViolet, omega) *
                      channel_sensitivity(kYellowViolet, rho, s.area_deg2, lum) *
                      (drop ? ecc_factor(kYvDrop, rho, s) : 1.0);
  // castleCSF eq. 18: contrasts of a D65 luminance modulation in each mechanism, Minkowski beta = 2.
  const double a = kD65Lms[0] + kD65Lms[1];
  const double rg_share = std::abs(kD65Lms[0] - kRgM * kD65Lms[1]) / a;
  const double yv_share = std::abs(-kD65Lms[0] - kD65Lms[1] + kYvS * kD65Lms[2]) / a;
  return {s_ach, std::hypot(rg_share * s_rg, yv_share * s_yv)};
}

double castle_sensitivity(const CsfStimulus& s, EccentricityTerm ecc) {
  const CsfParts p = castle_sensitivity_parts(s, ecc);
  return std::hypot(p.achromatic, p.chromatic);
}

double castle_disc_sensitivity(double radius_deg, double luminance_cd_m2, double ecc_deg, double vis_field_deg,
                               EccentricityTerm ecc) {
  constexpr double kDiscAreaDeg2 = 2.42437;  // castleCSF's fitted Gabor area for discs
  constexpr double kDiscBeta = 3.01142;      // and its summation exponent over the radius
  constexpr int kSteps = 100;                // 0.125 to 16 cpd, log-spaced
  double best = 0.0;
  for (int i = 0; i < kSteps; ++i) {
    const double rho = 0.125 * std::pow(128.0, double(i) / double(kSteps - 1));
    best = std::max(best, castle_sensitivity({rho, luminance_cd_m2, kDiscAreaDeg2, ecc_deg, vis_field_deg}, ecc));
  }
  return best * std::pow(radius_deg, 1.0 / kDiscBeta);
}

}  // namespace foveart::eval
