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

// Band b's squared threshold-unit contrast difference E and masking signal M, before pooling.
void band_energy(const BandInputs& in, const PerceptualMetric::BandTable& table, int ecc_steps,
                 const PerceptualDisplay& d, glm::vec2 gaze_px, foveation::Executor* ex, Plane& e, Plane& m) {
  const double scale = std::ldexp(1.0, in.band);
  const double view_distance_px = d.pixels_per_deg * kDegPerRad;
  e = Plane(in.test_band.width_px, in.test_band.height_px);
  m = Plane(e.width_px, e.height_px);
  for_rows(ex, e.height_px, [&](int y0, int y1) {
    for (int y = y0; y < y1; ++y)
      for (int x = 0; x < e.width_px; ++x) {
        const double dx = (x + 0.5) * scale - 0.5 - double(gaze_px.x), dy = (y + 0.5) * scale - 0.5 - double(gaze_px.y);
        const double ecc = ecc_of_distance(std::hypot(dx, dy), view_distance_px);
        const double lum = std::max(1e-3, double(in.ref_mean.at(x, y)));
        const double log_lum = std::log10(lum);
        const double w = temporal_weight(dx, dy, d.eye);
        const double log_s = (1.0 - w) * double(lookup(table.log_s_nasal, log_lum, ecc, ecc_steps)) +
                             w * double(lookup(table.log_s_temporal, log_lum, ecc, ecc_steps));
        const double s_over_lum = std::pow(10.0, log_s) / lum;
        const double t = s_over_lum * double(in.test_band.at(x, y)), r = s_over_lum * double(in.ref_band.at(x, y));
        e.at(x, y) = float((t - r) * (t - r));
        const double mask = std::min(std::abs(t), std::abs(r));
        m.at(x, y) = float(mask * mask);
      }
  });
}

// ColorVideoVDP's masking transducer, in threshold units: d^2 = D^2 / (1 + (k M)^q)^(2 / p).
void mask_band(Plane& e, const Plane& m, double energy_scale, bool masking) {
  for (std::size_t i = 0; i < e.v.size(); ++i) {
    const double d2 = energy_scale * double(e.v[i]);
    if (!masking) {
      e.v[i] = float(d2);
      continue;
    }
    const double mask = std::sqrt(std::max(0.0, energy_scale * double(m.v[i])));
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
  int band_count = 0;
  while (band_count < int(bands_.size()) &&
         (std::min(test.width_px, test.height_px) >> (band_count + 1)) >= kMinBandSidePx / 2)
    ++band_count;
  LaplacianPyramid pt, pr;
  two_tasks(executor, [&] { pt = laplacian_pyramid(luminance_plane(test, display_, nullptr), band_count); },
            [&] { pr = laplacian_pyramid(luminance_plane(reference, display_, nullptr), band_count); });
  Plane acc;
  for (int b = band_count - 1; b >= 0; --b) {
    Plane e, m;
    band_energy({pt.band[std::size_t(b)], pr.band[std::size_t(b)], pr.mean[std::size_t(b)], b},
                bands_[std::size_t(b)], ecc_steps_, display_, gaze_px, executor, e, m);
    const double sigma = bands_[std::size_t(b)].pool_sigma_px;
    two_tasks(executor, [&] { box3_blur(e, sigma); }, [&] { if (options_.masking) box3_blur(m, sigma); });
    mask_band(e, m, energy_scale_, options_.masking);
    if (!acc.v.empty()) {
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
