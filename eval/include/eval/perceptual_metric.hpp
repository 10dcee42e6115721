// A perceptual foveated difference metric: per pixel, the probability that an observer
// fixating the gaze point detects the difference between a test and a reference image
// (docs/lab/perceptual_metric.md). A model built once per display evaluates many pairs.
//
// Model: luminance (cd/m^2) of both images through the display; band-limited contrast on
// a Laplacian pyramid (Peli 1990); each band's contrast difference in threshold units
// through the castleCSF sensitivity (castle_csf.hpp) at the band's frequency, the local
// mean luminance and the pixel's eccentricity; contrast energy summed over the critical
// area A_c(rho) (Rovamo et al. 1993, the area model castleCSF uses), so that a Gabor of
// area A sums to castleCSF's sqrt(A / (A + A_c)); mutual contrast masking (the transducer
// of FovVideoVDP / ColorVideoVDP, Mantiuk et al. 2021, 2024); energy (beta = 2) summation
// over bands and a Weibull psychometric function, P = 1 - 0.5^(d^3.5) (probability
// summation, Quick 1974; Robson & Graham 1981), P = 0.5 at d = 1.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <glm/vec2.hpp>

#include "eval/castle_csf.hpp"
#include "eval/contrast_pyramid.hpp"
#include "foveation/display_model.hpp"
#include "foveation/display_transform.hpp"
#include "foveation/executor.hpp"
#include "foveation/image.hpp"
#include "metrics/image_metrics.hpp"

namespace foveart::eval {

enum class Eye : bool { kRight = false, kLeft = true };  // which visual field (nasal / temporal) a side is

// What the images hold. kRadiance: linear radiance, through PerceptualDisplay::transform to
// display-linear values. kSrgbEncoded: display values already sRGB-encoded (metrics::display_encode,
// a PNG's bytes / 255): the display's sRGB EOTF (IEC 61966-2-1) decodes them, the transform is
// not applied. Luminance is linear in the display-linear values either way.
enum class PerceptualInput : bool { kRadiance = false, kSrgbEncoded = true };

// What the observer sees: pixels to degrees as the project maps them (display_model.hpp:
// e = atan(d / D) around the gaze, D = pixels per degree * 180 / pi), and luminance.
struct PerceptualDisplay {
  double pixels_per_deg = 20.0;          // at the gaze point; > 0
  double white_luminance_cd_m2 = 100.0;  // what display value 1.0 (white) emits; > 0
  double black_luminance_cd_m2 = 0.1;    // what display value 0 emits (stray light, panel black); >= 0
  // Radiance -> display-linear values in [0, 1] (kRadiance input; a run's own transform may be
  // given). Luminance = black + (white - black) x Rec. 709 Y of the display-linear values.
  foveation::DisplayTransform transform = foveation::kClampOnly;
  PerceptualInput input = PerceptualInput::kRadiance;
  Eye eye = Eye::kRight;
};

// A rendered view's display for the metric: its pixels per degree at the gaze (the map's), the eye;
// the rest PerceptualDisplay's defaults.
PerceptualDisplay view_display(const metrics::EccentricityMap& map, Eye eye);

struct PerceptualOptions {
  EccentricityTerm eccentricity = EccentricityTerm::kOn;  // kOff: the control without the drop
  bool masking = true;
  // The sensitivity of castleCSF to a difference that flickers at this frequency (Hz): 0, a static
  // difference; the display's half frame rate, one that alternates every frame.
  double temporal_freq_hz = 0.0;
};

// One ring of metrics::kRingEdgesDeg.
struct PerceptualRing {
  double from_deg = 0.0;
  double to_deg = std::numeric_limits<double>::infinity();
  std::uint64_t pixels = 0;
  double p_mean = 0.0;             // mean detection probability over the ring's pixels
  double p_max = 0.0;              // largest
  double detected_fraction = 0.0;  // share of pixels with P >= 0.5
};

struct PerceptualResult {
  int width_px = 0;
  int height_px = 0;
  std::vector<float> p_detect;  // per pixel, row-major
  std::vector<PerceptualRing> rings;
  double p_mean = 0.0;
  double p_max = 0.0;
  double detected_fraction = 0.0;
};

struct GazeTables;  // per gaze, per pyramid level (perceptual_detail.hpp)

class PerceptualMetric {
 public:
  // Builds the sensitivity tables for images up to max_width_px x max_height_px on `display`.
  // `executor` (may be null) solves the tables' rows in parallel.
  [[nodiscard]] static bool create(const PerceptualDisplay& display, int max_width_px, int max_height_px,
                                   const PerceptualOptions& options, PerceptualMetric& out, std::string& error,
                                   foveation::Executor* executor = nullptr);

  // Detection probability of test against reference at gaze_px (screen pixels). Errors:
  // sizes differ or exceed the model's, non-finite pixels, gaze off the image.
  // `executor` (may be null) runs the bands' rows in parallel; no thread is started.
  [[nodiscard]] bool evaluate(const foveation::ImageRgb& test, const foveation::ImageRgb& reference,
                              glm::vec2 gaze_px, foveation::Executor* executor, PerceptualResult& out,
                              std::string& error) const;

  // How many times above its detection threshold the difference is: m such that the image whose
  // luminance is the reference's plus (test - reference) / m is detected at P max = 0.5 (the test
  // itself: P max >= 0.5 where m >= 1). The headroom a model of a less sensitive task would have to
  // explain. Bisection over log2(1 / m) in [-12, 12] to within 1/256 (0.3 %); 0: identical images or
  // not detected even amplified 4096 times (an amplified luminance stays at least the display's
  // black); 4096: detected even divided by 4096. With ring_multiples (may be null), each ring's
  // own multiple too, by its largest P (PerceptualResult::rings' order; 0 in a ring without
  // pixels): about 15 more evaluations a ring. Errors: as evaluate().
  [[nodiscard]] bool threshold_multiple(const foveation::ImageRgb& test, const foveation::ImageRgb& reference,
                                        glm::vec2 gaze_px, foveation::Executor* executor, double& multiple,
                                        std::string& error, std::vector<double>* ring_multiples = nullptr) const;

  const PerceptualDisplay& display() const { return display_; }

  // One band's tables over (log10 luminance, eccentricity) in both fields, per mechanism (0: the
  // achromatic, 1: the chromatic mechanisms' share of a luminance modulation, each with its own
  // critical area): log10 of the band's sensitivity sqrt(w_b), solved so that the bands together
  // give castleCSF's sensitivity to a Gabor at any frequency they cover (perceptual_metric.cpp).
  static constexpr int kMechanisms = 2;
  struct TableGrid {
    double log_lum_min = 0.0;  // the first column's log10 luminance
    int lum_steps = 0;         // columns, perceptual_detail.hpp's kLogLumStep apart
    int ecc_steps = 0;         // rows, kEccStepDeg apart from 0
  };
  struct BandTable {
    double freq_cyc_px = 0.0;  // the band's centre frequency, cycles per full-resolution pixel
    std::array<double, kMechanisms> pool_sigma_px{};  // each critical area's Gaussian sigma, band pixels
    std::array<std::vector<float>, kMechanisms> log_s_nasal, log_s_temporal;
  };

 private:
  static constexpr double kThresholdMultipleLog2Range = 12.0;
  static constexpr double kThresholdMultipleLog2Tolerance = 1.0 / 256.0;
  // evaluate() on checked luminance planes (cd/m^2) of equal size.
  void evaluate_luminance(const Plane& test_cd_m2, const Plane& reference_cd_m2, glm::vec2 gaze_px,
                          foveation::Executor* executor, PerceptualResult& out) const;

  PerceptualDisplay display_;
  PerceptualOptions options_;
  int max_width_px_ = 0;
  int max_height_px_ = 0;
  TableGrid grid_;
  std::vector<BandTable> bands_;
  // The last gaze's tables (eccentricity, field weight, ring per pixel), reused while the gaze and
  // the image size stay: a price list evaluates every setting at one gaze.
  struct GazeCache;
  std::shared_ptr<GazeCache> gaze_cache_;
  std::shared_ptr<const GazeTables> gaze_tables(glm::vec2 gaze_px, int w, int h, int levels,
                                                foveation::Executor* executor) const;
};

}  // namespace foveart::eval
