// The perceptual metric's evaluation of one image pair (perceptual_metric.hpp).
#include <eval/perceptual_metric.hpp>

#include <metrics/image_metrics.hpp>

#include "perceptual_detail.hpp"

namespace foveart::eval {
namespace {

using namespace perceptual_detail;

bool check_inputs(const foveation::ImageRgb& test, const foveation::ImageRgb& reference, glm::vec2 gaze_px,
                  int max_w, int max_h, std::string& error) {
  if (test.width_px != reference.width_px || test.height_px != reference.height_px ||
      test.rgb.size() != reference.rgb.size() || test.rgb.size() != test.pixel_count() * 3)
    return error = "perceptual metric: the test image is " + std::to_string(test.width_px) + "x" +
                   std::to_string(test.height_px) + ", the reference " + std::to_string(reference.width_px) + "x" +
                   std::to_string(reference.height_px),
           false;
  if (test.width_px < kMinBandSidePx || test.height_px < kMinBandSidePx || test.width_px > max_w ||
      test.height_px > max_h)
    return error = "perceptual metric: images must be 8x8 to " + std::to_string(max_w) + "x" + std::to_string(max_h) +
                   " pixels (the model's size), got " + std::to_string(test.width_px) + "x" +
                   std::to_string(test.height_px),
           false;
  if (!std::isfinite(gaze_px.x) || !std::isfinite(gaze_px.y) || gaze_px.x < 0.0f || gaze_px.y < 0.0f ||
      gaze_px.x > float(test.width_px) || gaze_px.y > float(test.height_px))
    return error = "perceptual metric: the gaze (" + std::to_string(gaze_px.x) + ", " + std::to_string(gaze_px.y) +
                   ") is off the image",
           false;
  for (const auto* img : {&test, &reference})
    for (std::size_t i = 0; i < img->rgb.size(); ++i)
      if (!std::isfinite(img->rgb[i]))
        return error = std::string("perceptual metric: the ") + (img == &test ? "test" : "reference") +
                       " image has a non-finite value at pixel " + std::to_string(i / 3),
               false;
  return true;
}

// Luminance (cd/m^2): black + (white - black) x Rec. 709 Y of the display values.
Plane luminance_plane(const foveation::ImageRgb& image, const PerceptualDisplay& d, foveation::Executor* ex) {
  Plane out(image.width_px, image.height_px);
  const double span = d.white_luminance_cd_m2 - d.black_luminance_cd_m2;
  for_rows(ex, image.height_px, [&](int y0, int y1) {
    for (int y = y0; y < y1; ++y)
      for (int x = 0; x < image.width_px; ++x) {
        const float* p = image.at(x, y);
        const glm::vec3 v = d.transform.apply({p[0], p[1], p[2]});
        out.at(x, y) = float(d.black_luminance_cd_m2 + span * (0.2126 * double(v.r) + 0.7152 * double(v.g) + 0.0722 * double(v.b)));
      }
  });
  return out;
}

struct BandInputs {
  const Plane& test_band;
  const Plane& ref_band;
  const Plane& ref_mean;
  int band;
};

// Band b's squared threshold-unit contrast difference per mechanism (E_a achromatic, E_c chromatic)
// and the masking signal M, before pooling.
struct BandEnergy {
  Plane e_ach, e_chr, mask;
};

void band_energy(const BandInputs& in, const PerceptualMetric::BandTable& table, const PerceptualMetric::TableGrid& grid,
                 const PerceptualDisplay& d, glm::vec2 gaze_px, foveation::Executor* ex, BandEnergy& out) {
  const double scale = std::ldexp(1.0, in.band / kBandsPerLevel);
  const double view_distance_px = d.pixels_per_deg * kDegPerRad;
  const int w_px = in.test_band.width_px, h_px = in.test_band.height_px;
  out.e_ach = Plane(w_px, h_px);
  out.e_chr = Plane(w_px, h_px);
  out.mask = Plane(w_px, h_px);
  for_rows(ex, h_px, [&](int y0, int y1) {
    for (int y = y0; y < y1; ++y)
      for (int x = 0; x < w_px; ++x) {
        const double dx = (x + 0.5) * scale - 0.5 - double(gaze_px.x), dy = (y + 0.5) * scale - 0.5 - double(gaze_px.y);
        const double ecc = ecc_of_distance(std::hypot(dx, dy), view_distance_px);
        const double lum = std::max(kMinLuminance, double(in.ref_mean.at(x, y)));
        const double log_lum = std::log10(lum);
        const double tw = temporal_weight(dx, dy, d.eye);
        double w2[2];
        for (std::size_t m = 0; m < 2; ++m) {
          const double log_s = (1.0 - tw) * double(lookup(table.log_s_nasal[m], log_lum, ecc, grid)) +
                               tw * double(lookup(table.log_s_temporal[m], log_lum, ecc, grid));
          w2[m] = std::pow(10.0, 2.0 * log_s);
        }
        const double t = double(in.test_band.at(x, y)) / lum, r = double(in.ref_band.at(x, y)) / lum;
        out.e_ach.at(x, y) = float(w2[0] * (t - r) * (t - r));
        out.e_chr.at(x, y) = float(w2[1] * (t - r) * (t - r));
        const double mask = std::min(std::abs(t), std::abs(r));
        out.mask.at(x, y) = float((w2[0] + w2[1]) * mask * mask);
      }
  });
}

// ColorVideoVDP's masking transducer, in threshold units: d^2 = D^2 / (1 + (k M)^q)^(2 / p).
void mask_band(Plane& e, const Plane& m, bool masking) {
  for (std::size_t i = 0; i < e.v.size(); ++i) {
    const double d2 = double(e.v[i]);
    if (!masking) {
      e.v[i] = float(d2);
      continue;
    }
    const double mask = std::sqrt(std::max(0.0, double(m.v[i])));
    e.v[i] = float(d2 / std::pow(1.0 + std::pow(kMaskK * mask, kMaskQ), 2.0 / kMaskP));
  }
}

// Runs a and b, on two of the executor's threads when there is one.
void two_tasks(foveation::Executor* ex, const std::function<void()>& a, const std::function<void()>& b) {
  if (ex == nullptr) return a(), b();
  ex->parallel_for(2, [&](std::size_t i) { i == 0 ? a() : b(); });
}

void summarize(const PerceptualDisplay& d, glm::vec2 gaze_px, PerceptualResult& out) {
  const double view_distance_px = d.pixels_per_deg * kDegPerRad;
  out.rings.assign(metrics::kRingCount, PerceptualRing{});
  std::vector<double> sums(metrics::kRingCount, 0.0), detected(metrics::kRingCount, 0.0);
  double total = 0.0, total_detected = 0.0;
  for (std::size_t r = 0; r < metrics::kRingCount; ++r) {
    out.rings[r].from_deg = metrics::kRingEdgesDeg[r];
    out.rings[r].to_deg = metrics::kRingEdgesDeg[r + 1];
  }
  for (int y = 0; y < out.height_px; ++y)
    for (int x = 0; x < out.width_px; ++x) {
      const double ecc = ecc_of_distance(std::hypot(double(x) - double(gaze_px.x), double(y) - double(gaze_px.y)), view_distance_px);
      std::size_t r = 0;
      while (r + 1 < metrics::kRingCount && ecc >= metrics::kRingEdgesDeg[r + 1]) ++r;
      const double p = out.p_detect[std::size_t(y) * std::size_t(out.width_px) + std::size_t(x)];
      PerceptualRing& ring = out.rings[r];
      ++ring.pixels;
      sums[r] += p;
      detected[r] += p >= 0.5 ? 1.0 : 0.0;
      ring.p_max = std::max(ring.p_max, p);
      total += p;
      total_detected += p >= 0.5 ? 1.0 : 0.0;
      out.p_max = std::max(out.p_max, p);
    }
  for (std::size_t r = 0; r < metrics::kRingCount; ++r)
    if (out.rings[r].pixels > 0) {
      out.rings[r].p_mean = sums[r] / double(out.rings[r].pixels);
      out.rings[r].detected_fraction = detected[r] / double(out.rings[r].pixels);
    }
  out.p_mean = total / double(out.p_detect.size());
  out.detected_fraction = total_detected / double(out.p_detect.size());
}

}  // namespace

bool PerceptualMetric::evaluate(const foveation::ImageRgb& test, const foveation::ImageRgb& reference,
                                glm::vec2 gaze_px, foveation::Executor* executor, PerceptualResult& out,
                                std::string& error) const {
  if (bands_.empty()) return error = "perceptual metric: the model was not created", false;
  if (!check_inputs(test, reference, gaze_px, max_width_px_, max_height_px_, error)) return false;
  const int levels = std::min(int(bands_.size()) / kBandsPerLevel, level_count(test.width_px, test.height_px));
  const int band_count = levels * kBandsPerLevel;
  LaplacianPyramid pt, pr;
  two_tasks(executor, [&] { pt = laplacian_pyramid(luminance_plane(test, display_, nullptr), levels); },
            [&] { pr = laplacian_pyramid(luminance_plane(reference, display_, nullptr), levels); });
  Plane acc;
  for (int b = band_count - 1; b >= 0; --b) {
    BandEnergy be;
    band_energy({pt.band[std::size_t(b)], pr.band[std::size_t(b)], pr.mean[std::size_t(b / kBandsPerLevel)], b},
                bands_[std::size_t(b)], grid_, display_, gaze_px, executor, be);
    const auto& sigma = bands_[std::size_t(b)].pool_sigma_px;
    two_tasks(executor, [&] { box3_blur(be.e_ach, sigma[0]); box3_blur(be.e_chr, sigma[1]); },
              [&] { if (options_.masking) box3_blur(be.mask, sigma[0]); });
    Plane& e = be.e_ach;
    for (std::size_t i = 0; i < e.v.size(); ++i) e.v[i] += be.e_chr.v[i];
    mask_band(e, be.mask, options_.masking);
    if (!acc.v.empty() && acc.width_px == e.width_px && acc.height_px == e.height_px) {
      for (std::size_t i = 0; i < e.v.size(); ++i) e.v[i] += acc.v[i];
    } else if (!acc.v.empty()) {
      const Plane up = pyramid_expand(acc, e.width_px, e.height_px);
      for (std::size_t i = 0; i < e.v.size(); ++i) e.v[i] += std::max(0.0f, up.v[i]);
    }
    acc = std::move(e);
  }
  out = PerceptualResult{};
  out.width_px = test.width_px;
  out.height_px = test.height_px;
  out.p_detect.resize(acc.v.size());
  for (std::size_t i = 0; i < acc.v.size(); ++i)
    out.p_detect[i] = float(1.0 - std::exp(std::log(0.5) * std::pow(std::max(0.0, double(acc.v[i])), 0.5 * kPsychometricBeta)));
  summarize(display_, gaze_px, out);
  return true;
}

}  // namespace foveart::eval
