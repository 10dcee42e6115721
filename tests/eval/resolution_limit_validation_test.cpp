// The perceptual metric's acuity against a second human dataset: the resolution limit of Ashraf,
// Chapiro & Mantiuk ("Resolution limit of the eye: how many pixels can we see?", arXiv:2410.06068;
// tests/data/resolution_limit_achromatic.csv). At 0, 10 and 20 deg, 16 to 18 observers each gave
// the pixels per degree beyond which they could no longer tell a one-pixel black-and-white grating
// (contrast 0.913 on 100 cd/m^2, 2 deg) from a uniform field. The metric's limit is the pixels per
// degree at which that grating sits at its threshold:
//  - through its CSF (castle_csf.hpp): the grating's fundamental, of frequency ppd / 2 and 4 / pi
//    the square wave's contrast (a one-pixel grating on a display is a square wave);
//  - through the image path: the grating drawn pixel by pixel, where the metric's largest P is 0.5.
// The yardstick is the observers' own spread, the SD of their log10 limits: the metric models one
// standard observer, and within 2 SD of the median lies about 95 % of a population.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

#include "castle_validation.hpp"
#include "eval/castle_csf.hpp"
#include "eval/perceptual_metric.hpp"
#include "foveation/display_model.hpp"
#include "under_sanitizer.hpp"

namespace {

using foveart::eval::EccentricityTerm;

constexpr double kDegPerRad = 180.0 / M_PI;
constexpr std::array<double, 3> kEccentricitiesDeg = {0.0, 10.0, 20.0};
constexpr double kToleranceSd = 2.0;
constexpr double kTemporalField = 0.0, kNasalField = 180.0;  // castle_csf.hpp's vis_field_deg

// One eccentricity's observers: the stimulus and log10 of each one's limit (pixels per degree).
struct Observers {
  double ecc_deg = 0.0;
  double luminance_cd_m2 = 0.0, size_deg = 0.0, contrast = 0.0;
  std::vector<double> log10_ppd;

  double median() const {
    std::vector<double> v = log10_ppd;
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
  }
  double sd() const {
    double mean = 0, m2 = 0;
    for (double x : log10_ppd) mean += x;
    mean /= double(log10_ppd.size());
    for (double x : log10_ppd) m2 += (x - mean) * (x - mean);
    return std::sqrt(m2 / double(log10_ppd.size() - 1));
  }
  // How many observer SDs a predicted limit lies from the median (positive: a sharper eye).
  double deviation_sd(double predicted_ppd) const { return (std::log10(predicted_ppd) - median()) / sd(); }
};

Observers load_observers(double ecc_deg) {
  Observers o;
  o.ecc_deg = ecc_deg;
  for (const std::vector<std::string>& f : foveart::test::test_data_rows("resolution_limit_achromatic.csv")) {
    if (f.size() != 14 || std::stod(f[2]) != ecc_deg) continue;
    o.luminance_cd_m2 = std::stod(f[1]);
    o.size_deg = std::stod(f[4]);
    o.contrast = 1.0 / std::stod(f[13]);
    o.log10_ppd.push_back(std::log10(std::stod(f[10])));
  }
  return o;
}

// The largest pixels per degree in (lo, hi) at which `seen(ppd)` still holds, by bisection over log
// ppd to within 1 %, given that it holds at lo and fails at hi.
template <class Seen>
double bisect_limit_ppd(double lo, double hi, const Seen& seen) {
  double a = std::log(lo), b = std::log(hi);
  while (b - a > 0.01) {
    const double mid = 0.5 * (a + b);
    (seen(std::exp(mid)) ? a : b) = mid;
  }
  return std::exp(0.5 * (a + b));
}

// The same over [lo, hi]: the bound where `seen` holds at both ends or fails at both.
template <class Seen>
double limit_ppd(double lo, double hi, const Seen& seen) {
  if (!seen(lo)) return lo;
  if (seen(hi)) return hi;
  return bisect_limit_ppd(lo, hi, seen);
}

// Through the CSF: the square wave's fundamental, at the limit frequency ppd / 2, sits at threshold.
double csf_limit_ppd(const Observers& o, double vis_field_deg, EccentricityTerm term) {
  const double area_deg2 = M_PI * 0.25 * o.size_deg * o.size_deg;
  const double fundamental_contrast = 4.0 / M_PI * o.contrast;
  return limit_ppd(8.0, 800.0, [&](double ppd) {
    const double s = foveart::eval::castle_sensitivity(
        {0.5 * ppd, o.luminance_cd_m2, area_deg2, o.ecc_deg, vis_field_deg, 0.0}, term);
    return s * fundamental_contrast >= 1.0;
  });
}

// The grating on a flat display whose pixels per degree is `ppd` at the stimulus (the metric's
// mapping, e = atan(d / D)), ecc_deg right of the gaze (the right eye's temporal field, the left
// eye's nasal one): pixel columns alternately above and below the background by the contrast, under
// a Gaussian window of the data's area (sigma = size / 2, castleCSF's area pi sigma^2 = the 2 deg
// disc's).
class OnePixelGrating {
 public:
  OnePixelGrating(const Observers& o, double ppd, foveart::eval::Eye eye) : contrast_(o.contrast) {
    const double e = o.ecc_deg / kDegPerRad;
    display_.pixels_per_deg = ppd * std::cos(e) * std::cos(e);
    display_.white_luminance_cd_m2 = 2.0 * o.luminance_cd_m2;  // the background is value 0.5
    display_.black_luminance_cd_m2 = 0.0;
    display_.eye = eye;
    ppd_radial_ = ppd;
    ppd_tangential_ = ppd * std::cos(e);
    sigma_deg_ = 0.5 * o.size_deg;
    const int half_x = int(std::ceil(3.0 * sigma_deg_ * ppd_radial_)) + 8;
    const int half_y = int(std::ceil(3.0 * sigma_deg_ * ppd_tangential_)) + 8;
    const double dist_px = display_.pixels_per_deg * kDegPerRad * std::tan(e);
    gaze_ = {float(half_x), float(half_y)};
    cx_ = half_x + int(std::lround(dist_px));
    cy_ = half_y;
    width_ = cx_ + half_x + 1;
    height_ = 2 * half_y + 1;
  }

  // The metric's largest detection probability for the grating against the uniform field.
  double p_max(EccentricityTerm term) const {
    foveart::eval::PerceptualMetric m;
    foveart::eval::PerceptualResult out;
    std::string error;
    EXPECT_TRUE(foveart::eval::PerceptualMetric::create(display_, width_, height_, {term, true, 0.0}, m, error))
        << error;
    EXPECT_TRUE(m.evaluate(image(contrast_), image(0.0), gaze_, nullptr, out, error)) << error;
    return out.p_max;
  }

 private:
  foveart::foveation::ImageRgb image(double contrast) const {
    foveart::foveation::ImageRgb img(width_, height_);
    for (int y = 0; y < height_; ++y)
      for (int x = 0; x < width_; ++x) {
        const double u = (x - cx_) / ppd_radial_, v = (y - cy_) / ppd_tangential_;
        const double window = std::exp(-(u * u + v * v) / (2.0 * sigma_deg_ * sigma_deg_));
        const double sign = (x - cx_) % 2 == 0 ? 1.0 : -1.0;
        std::fill_n(img.at(x, y), 3, float(0.5 * (1.0 + contrast * window * sign)));
      }
    return img;
  }

  double contrast_ = 0.0, ppd_radial_ = 0.0, ppd_tangential_ = 0.0, sigma_deg_ = 0.0;
  foveart::eval::PerceptualDisplay display_;
  glm::vec2 gaze_{0.0f};
  int width_ = 0, height_ = 0, cx_ = 0, cy_ = 0;
};

bool image_path_sees(const Observers& o, double ppd, foveart::eval::Eye eye, EccentricityTerm term) {
  return OnePixelGrating(o, ppd, eye).p_max(term) >= 0.5;
}

std::string verdict(double deviation_sd, bool asserted) {
  const bool within = std::abs(deviation_sd) <= kToleranceSd;
  return within ? (asserted ? "within, asserted" : "within") : (asserted ? "MISS, asserted" : "MISS, printed");
}

}  // namespace

TEST(ResolutionLimitValidation, DataShippedForThreeEccentricities) {
  const std::array<std::size_t, 3> observers = {18, 16, 16};
  for (std::size_t i = 0; i < kEccentricitiesDeg.size(); ++i) {
    const Observers o = load_observers(kEccentricitiesDeg[i]);
    EXPECT_EQ(o.log10_ppd.size(), observers[i]) << kEccentricitiesDeg[i] << " deg";
    EXPECT_DOUBLE_EQ(o.luminance_cd_m2, 100.0);
    EXPECT_DOUBLE_EQ(o.size_deg, 2.0);
    EXPECT_NEAR(o.contrast, 0.913, 1e-3);
  }
}

// The CSF path, in both horizontal fields (a stimulus beside the gaze falls in one eye's temporal
// field and the other's nasal one), against the median within kToleranceSd observer SDs at 10 and
// 20 deg; the control without the eccentricity term must miss there. At the fovea the CSF's limit
// is a printed miss: castleCSF's high-frequency fall is fitted to data up to 32 cpd (the shipped
// rows' highest) and the limit lies beyond, near 95 cpd; a display below about 190 pixels per degree
// shows no such frequency, and the metric only sees frequencies the display shows.
TEST(ResolutionLimitValidation, CsfPathWithinTheObserversSpread) {
  std::ostringstream table;
  table << "\nresolution limit, CSF path (pixels per degree; deviation in observer SDs of log10 ppd)\n"
        << "| ecc | observers | median | SD log10 | temporal field | nasal field | control (no eccentricity term) |\n"
        << "|---|---|---|---|---|---|---|\n";
  for (const double e : kEccentricitiesDeg) {
    const Observers o = load_observers(e);
    const bool asserted = e > 0.0;
    const double temporal = csf_limit_ppd(o, kTemporalField, EccentricityTerm::kOn);
    const double nasal = csf_limit_ppd(o, kNasalField, EccentricityTerm::kOn);
    const double control = csf_limit_ppd(o, kTemporalField, EccentricityTerm::kOff);
    char line[320];
    std::snprintf(line, sizeof line,
                  "| %.0f deg | %zu | %.1f | %.3f | %.1f (%+.2f, %s) | %.1f (%+.2f, %s) | %.1f (%+.2f) |\n", e,
                  o.log10_ppd.size(), std::pow(10.0, o.median()), o.sd(), temporal, o.deviation_sd(temporal),
                  verdict(o.deviation_sd(temporal), asserted).c_str(), nasal, o.deviation_sd(nasal),
                  verdict(o.deviation_sd(nasal), asserted).c_str(), control, o.deviation_sd(control));
    table << line;
    if (!asserted) continue;
    EXPECT_LE(std::abs(o.deviation_sd(temporal)), kToleranceSd) << e << " deg, temporal field";
    EXPECT_LE(std::abs(o.deviation_sd(nasal)), kToleranceSd) << e << " deg, nasal field";
    EXPECT_GT(o.deviation_sd(control), kToleranceSd) << e << " deg, control";
  }
  std::cout << table.str();
}

// The image path, the grating drawn at one pixel per bar, off the fovea (the product traces the
// fovea pixel-exact), in both horizontal fields. What judges foveated images is this path, and
// one-pixel detail is what sparse points lose, so the property asserted is the one the "nobody can
// see this" claims rest on: the metric never credits the eye with less resolution than the median
// observer has (it sees the grating at the median's pixels per degree). Its own limit is printed
// (not under the sanitizers): how far above the median it lies. With the eccentricity term it no
// longer sees the grating at four times the median; the control, without it, still does.
TEST(ResolutionLimitValidation, ImagePathAtOnePixelPerBarIsNoLessAcuteThanTheMedianObserver) {
  using foveart::eval::Eye;
  std::ostringstream table;
  table << "\nresolution limit, image path at one pixel per bar (pixels per degree; deviation in observer SDs)\n"
        << "| ecc | median | temporal field | nasal field |\n|---|---|---|---|\n";
  for (const double e : {10.0, 20.0}) {
    const Observers o = load_observers(e);
    const double median_ppd = std::pow(10.0, o.median());
    std::string cells[2];
    for (const Eye eye : {Eye::kRight, Eye::kLeft}) {  // the stimulus right of the gaze: temporal, nasal
      const char* field = eye == Eye::kRight ? "temporal" : "nasal";
      const auto sees = [&](double ppd) { return image_path_sees(o, ppd, eye, EccentricityTerm::kOn); };
      const bool at_median = sees(median_ppd), at_four_medians = sees(4.0 * median_ppd);
      EXPECT_TRUE(at_median) << e << " deg, " << field;
      EXPECT_FALSE(at_four_medians) << e << " deg, " << field;
      if (foveart::test::kUnderSanitizer) {
        cells[eye == Eye::kLeft] = "seen at the median";
        continue;
      }
      const double limit = !at_median        ? median_ppd
                           : at_four_medians ? 4.0 * median_ppd
                                             : bisect_limit_ppd(median_ppd, 4.0 * median_ppd, sees);
      char cell[80];
      std::snprintf(cell, sizeof cell, "%.1f (%+.2f)", limit, o.deviation_sd(limit));
      cells[eye == Eye::kLeft] = cell;
    }
    EXPECT_TRUE(image_path_sees(o, 4.0 * median_ppd, Eye::kRight, EccentricityTerm::kOff)) << e << " deg, control";
    char line[200];
    std::snprintf(line, sizeof line, "| %.0f deg | %.1f | %s | %s |\n", e, median_ppd, cells[0].c_str(),
                  cells[1].c_str());
    table << line;
  }
  std::cout << table.str();
}

// What docs/foveation.md says of the point set's eye model: the thesis's cut-off (eq. 2, Geisler &
// Perry 1998), the highest frequency seen at full contrast, lies below every observer's measured limit
// at 10 and 20 deg, so a full-contrast one-pixel grating beyond the pixel grid is under-sampled.
TEST(ResolutionLimitValidation, ThesisCutoffLiesBelowEveryObserverOffTheFovea) {
  std::ostringstream table;
  table << "\nthe thesis's cut-off (eq. 2) as a resolution limit, pixels per degree\n"
        << "| ecc | eq. 2 | observers' lowest | median |\n|---|---|---|---|\n";
  for (const double e : kEccentricitiesDeg) {
    const Observers o = load_observers(e);
    const double thesis_ppd = 2.0 * foveart::foveation::cutoff_frequency_cpd(e);
    const double lowest_ppd = std::pow(10.0, *std::min_element(o.log10_ppd.begin(), o.log10_ppd.end()));
    char line[160];
    std::snprintf(line, sizeof line, "| %.0f deg | %.1f | %.1f | %.1f |\n", e, thesis_ppd, lowest_ppd,
                  std::pow(10.0, o.median()));
    table << line;
    if (e > 0.0) {
      EXPECT_LT(thesis_ppd, lowest_ppd) << e << " deg";
    }
  }
  std::cout << table.str();
}
