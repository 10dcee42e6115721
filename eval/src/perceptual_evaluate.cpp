// The perceptual metric's evaluation of one image pair (perceptual_metric.hpp).
//
// Speed: every plane pass runs as row (or column-strip) tasks on the executor; what depends on
// the gaze alone (eccentricity, field weight and table row per pixel and level, the ring of
// every pixel) is built once per gaze and reused; the table column (log luminance) once per
// level for both of its bands; transcendental functions in float where the result is a float.
#include <eval/perceptual_metric.hpp>

#include <foveation/srgb.hpp>
#include <metrics/image_metrics.hpp>

#include "perceptual_detail.hpp"

#include <map>
#include <vector>

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

// A pixel's display-linear colour: the transform of radiance, or the sRGB EOTF of encoded values.
glm::vec3 display_linear(const float* p, const PerceptualDisplay& d) {
  if (d.input == PerceptualInput::kRadiance) return d.transform.apply({p[0], p[1], p[2]});
  const auto eotf = [](float c) { return foveation::srgb_to_linear(std::clamp(c, 0.0f, 1.0f)); };
  return {eotf(p[0]), eotf(p[1]), eotf(p[2])};
}

// Luminance (cd/m^2): black + (white - black) x Rec. 709 Y of the display-linear values.
Plane luminance_plane(const foveation::ImageRgb& image, const PerceptualDisplay& d, foveation::Executor* ex) {
  Plane out = Plane::uninitialized(image.width_px, image.height_px);
  const double span = d.white_luminance_cd_m2 - d.black_luminance_cd_m2;
  for_rows(ex, image.height_px, [&](int y0, int y1) {
    for (int y = y0; y < y1; ++y)
      for (int x = 0; x < image.width_px; ++x) {
        const glm::vec3 v = display_linear(image.at(x, y), d);
        out.at(x, y) = float(d.black_luminance_cd_m2 + span * (0.2126 * double(v.r) + 0.7152 * double(v.g) + 0.0722 * double(v.b)));
      }
  });
  return out;
}

// Level `level` of the gaze tables: per pixel of that level's planes, the table row (eccentricity
// / kEccStepDeg, clamped to the table) and the temporal field's weight; at level 0 the ring too.
void gaze_level(const PerceptualDisplay& d, const PerceptualMetric::TableGrid& grid, int level, int w, int h,
                foveation::Executor* ex, GazeTables& t) {
  const double scale = std::ldexp(1.0, level), view_distance_px = d.pixels_per_deg * kDegPerRad;
  Plane ecc_row = Plane::uninitialized(w, h), tw = Plane::uninitialized(w, h);
  const glm::vec2 gaze = t.gaze_px;
  for_rows(ex, h, [&](int y0, int y1) {
    for (int y = y0; y < y1; ++y)
      for (int x = 0; x < w; ++x) {
        const double dx = (x + 0.5) * scale - 0.5 - double(gaze.x), dy = (y + 0.5) * scale - 0.5 - double(gaze.y);
        const double ecc = ecc_of_distance(std::hypot(dx, dy), view_distance_px);
        ecc_row.at(x, y) = float(std::clamp(ecc / kEccStepDeg, 0.0, double(grid.ecc_steps - 1) - 1e-6));
        tw.at(x, y) = float(temporal_weight(dx, dy, d.eye));
        if (level > 0) continue;
        std::size_t r = 0;
        while (r + 1 < metrics::kRingCount && ecc >= metrics::kRingEdgesDeg[r + 1]) ++r;
        t.ring[std::size_t(y) * std::size_t(w) + std::size_t(x)] = std::uint8_t(r);
      }
  });
  t.ecc_row.push_back(std::move(ecc_row));
  t.temporal_weight.push_back(std::move(tw));
}

std::shared_ptr<const GazeTables> build_gaze_tables(const PerceptualDisplay& d, const PerceptualMetric::TableGrid& grid,
                                                    glm::vec2 gaze_px, int w, int h, int levels, foveation::Executor* ex) {
  auto t = std::make_shared<GazeTables>();
  t->gaze_px = gaze_px;
  t->width_px = w;
  t->height_px = h;
  t->levels = levels;
  t->ring.resize(std::size_t(w) * std::size_t(h));
  for (int level = 0; level < levels; ++level, w = (w + 1) / 2, h = (h + 1) / 2) gaze_level(d, grid, level, w, h, ex, *t);
  return t;
}

// The table column (log10 luminance - its minimum) / kLogLumStep of each pixel's local mean, clamped.
Plane lum_columns(const Plane& mean, const PerceptualMetric::TableGrid& g, foveation::Executor* ex) {
  Plane out = Plane::uninitialized(mean.width_px, mean.height_px);
  for_rows(ex, mean.height_px, [&](int y0, int y1) {
    for (int y = y0; y < y1; ++y)
      for (int x = 0; x < mean.width_px; ++x) {
        const double log_lum = std::log10(std::max(kMinLuminance, double(mean.at(x, y))));
        out.at(x, y) = float(std::clamp((log_lum - g.log_lum_min) / kLogLumStep, 0.0, double(g.lum_steps - 1) - 1e-6));
      }
  });
  return out;
}

struct BandInputs {
  const Plane& test_band;
  const Plane& ref_band;
  const Plane& ref_mean;
  const Plane& lum_column;  // lum_columns of ref_mean
  const Plane& ecc_row;     // the gaze tables' level
  const Plane& temporal_weight;
};

// Band b's squared threshold-unit contrast difference per mechanism (E_a achromatic, E_c chromatic)
// and the masking signal M, before pooling.
struct BandEnergy {
  Plane e_ach, e_chr, mask;
};

// A band's squared sensitivity per mechanism at one pixel: both fields' tables, bilinear in
// (luminance column u, eccentricity row v), blended by the temporal weight tw.
void band_weights(const PerceptualMetric::BandTable& table, int lum_steps, float u, float v, float tw, float w2[2]) {
  constexpr double kTwoLn10 = 2.0 * std::numbers::ln10;
  const int l = int(u), e = int(v);
  const double fu = double(u) - l, fv = double(v) - e;
  const std::size_t i00 = std::size_t(e * lum_steps + l), i10 = i00 + std::size_t(lum_steps);
  const auto bilinear = [&](const std::vector<float>& t) {
    return (1 - fv) * ((1 - fu) * double(t[i00]) + fu * double(t[i00 + 1])) +
           fv * ((1 - fu) * double(t[i10]) + fu * double(t[i10 + 1]));
  };
  for (std::size_t m = 0; m < 2; ++m) {
    const double log_s = (1.0 - double(tw)) * bilinear(table.log_s_nasal[m]) + double(tw) * bilinear(table.log_s_temporal[m]);
    w2[m] = std::exp(float(kTwoLn10 * log_s));
  }
}

void band_energy(const BandInputs& in, const PerceptualMetric::BandTable& table, const PerceptualMetric::TableGrid& grid,
                 foveation::Executor* ex, BandEnergy& out) {
  const int w_px = in.test_band.width_px, h_px = in.test_band.height_px;
  out.e_ach = Plane::uninitialized(w_px, h_px);
  out.e_chr = Plane::uninitialized(w_px, h_px);
  out.mask = Plane::uninitialized(w_px, h_px);
  for_rows(ex, h_px, [&](int y0, int y1) {
    for (int y = y0; y < y1; ++y)
      for (int x = 0; x < w_px; ++x) {
        float w2[2];
        band_weights(table, grid.lum_steps, in.lum_column.at(x, y), in.ecc_row.at(x, y), in.temporal_weight.at(x, y), w2);
        const float lum = std::max(float(kMinLuminance), in.ref_mean.at(x, y));
        const float t = in.test_band.at(x, y) / lum, r = in.ref_band.at(x, y) / lum;
        out.e_ach.at(x, y) = w2[0] * (t - r) * (t - r);
        out.e_chr.at(x, y) = w2[1] * (t - r) * (t - r);
        const float mask = std::min(std::abs(t), std::abs(r));
        out.mask.at(x, y) = (w2[0] + w2[1]) * mask * mask;
      }
  });
}

// Both mechanisms' pooled energy through ColorVideoVDP's masking transducer, in threshold units,
// d^2 = D^2 / (1 + (k M)^q)^(2 / p), plus the coarser bands' sum `below` (null: none; clamped at 0
// when it was expanded from a coarser level): into be.e_ach.
void combine_band(BandEnergy& be, const Plane* below, bool expanded, bool masking, foveation::Executor* ex) {
  const float k = float(kMaskK), q = float(kMaskQ), two_over_p = float(2.0 / kMaskP);
  Plane& e = be.e_ach;
  for_rows(ex, e.height_px, [&](int y0, int y1) {
    const std::size_t a = std::size_t(y0) * std::size_t(e.width_px), b = std::size_t(y1) * std::size_t(e.width_px);
    for (std::size_t i = a; i < b; ++i) {
      float d2 = e.v[i] + be.e_chr.v[i];
      if (masking) d2 /= std::pow(1.0f + std::pow(k * std::sqrt(std::max(0.0f, be.mask.v[i])), q), two_over_p);
      if (below != nullptr) d2 += expanded ? std::max(0.0f, below->v[i]) : below->v[i];
      e.v[i] = d2;
    }
  });
}

void summarize(const GazeTables& gt, foveation::Executor* ex, PerceptualResult& out) {
  constexpr std::size_t kRings = metrics::kRingCount;
  struct RowSums {
    std::array<std::uint64_t, kRings> pixels{}, detected{};
    std::array<double, kRings> sum{};
    std::array<float, kRings> max{};
  };
  std::vector<RowSums> rows(std::size_t(out.height_px));
  for_rows(ex, out.height_px, [&](int y0, int y1) {
    for (int y = y0; y < y1; ++y)
      for (int x = 0; x < out.width_px; ++x) {
        const std::size_t i = std::size_t(y) * std::size_t(out.width_px) + std::size_t(x), r = gt.ring[i];
        const float p = out.p_detect[i];
        RowSums& s = rows[std::size_t(y)];
        ++s.pixels[r];
        s.sum[r] += double(p);
        s.detected[r] += p >= 0.5f ? 1 : 0;
        s.max[r] = std::max(s.max[r], p);
      }
  });
  out.rings.assign(kRings, PerceptualRing{});
  std::array<double, kRings> sums{}, detected{};
  for (std::size_t r = 0; r < kRings; ++r) {
    out.rings[r].from_deg = metrics::kRingEdgesDeg[r];
    out.rings[r].to_deg = metrics::kRingEdgesDeg[r + 1];
  }
  for (const RowSums& s : rows)
    for (std::size_t r = 0; r < kRings; ++r) {
      out.rings[r].pixels += s.pixels[r];
      sums[r] += s.sum[r];
      detected[r] += double(s.detected[r]);
      out.rings[r].p_max = std::max(out.rings[r].p_max, double(s.max[r]));
    }
  double total = 0.0, total_detected = 0.0;
  for (std::size_t r = 0; r < kRings; ++r) {
    total += sums[r];
    total_detected += detected[r];
    out.p_max = std::max(out.p_max, out.rings[r].p_max);
    if (out.rings[r].pixels == 0) continue;
    out.rings[r].p_mean = sums[r] / double(out.rings[r].pixels);
    out.rings[r].detected_fraction = detected[r] / double(out.rings[r].pixels);
  }
  out.p_mean = total / double(out.p_detect.size());
  out.detected_fraction = total_detected / double(out.p_detect.size());
}

}  // namespace

std::shared_ptr<const GazeTables> PerceptualMetric::gaze_tables(glm::vec2 gaze_px, int w, int h, int levels,
                                                                foveation::Executor* executor) const {
  const auto fits = [&](const std::shared_ptr<const GazeTables>& t) {
    return t && t->gaze_px == gaze_px && t->width_px == w && t->height_px == h && t->levels == levels;
  };
  {
    const std::lock_guard<std::mutex> lock(gaze_cache_->mutex);
    if (fits(gaze_cache_->last)) return gaze_cache_->last;
  }
  std::shared_ptr<const GazeTables> t = build_gaze_tables(display_, grid_, gaze_px, w, h, levels, executor);
  const std::lock_guard<std::mutex> lock(gaze_cache_->mutex);
  gaze_cache_->last = t;
  return t;
}

bool PerceptualMetric::evaluate(const foveation::ImageRgb& test, const foveation::ImageRgb& reference,
                                glm::vec2 gaze_px, foveation::Executor* executor, PerceptualResult& out,
                                std::string& error) const {
  if (bands_.empty()) return error = "perceptual metric: the model was not created", false;
  if (!check_inputs(test, reference, gaze_px, max_width_px_, max_height_px_, error)) return false;
  evaluate_luminance(luminance_plane(test, display_, executor), luminance_plane(reference, display_, executor), gaze_px,
                     executor, out);
  return true;
}

bool PerceptualMetric::threshold_multiple(const foveation::ImageRgb& test, const foveation::ImageRgb& reference,
                                          glm::vec2 gaze_px, foveation::Executor* executor, double& multiple,
                                          std::string& error, std::vector<double>* ring_multiples) const {
  if (bands_.empty()) return error = "perceptual metric: the model was not created", false;
  if (!check_inputs(test, reference, gaze_px, max_width_px_, max_height_px_, error)) return false;
  const Plane lt = luminance_plane(test, display_, executor), lr = luminance_plane(reference, display_, executor);
  // The largest P of the image (index 0) and of each ring (1...) at reference + scale x (test -
  // reference), in luminance; amplified, at least the display's black. Each scale is evaluated once.
  std::map<double, std::vector<double>> p_max_at_scale;
  const auto p_max_at = [&](double log2_scale) -> const std::vector<double>& {
    const auto [it, added] = p_max_at_scale.try_emplace(log2_scale);
    if (!added) return it->second;
    Plane scaled = Plane::uninitialized(lt.width_px, lt.height_px);
    const float scale = float(std::exp2(log2_scale)), floor_cd_m2 = float(display_.black_luminance_cd_m2);
    const std::size_t row = std::size_t(lt.width_px);
    for_rows(executor, lt.height_px, [&](int y0, int y1) {
      for (std::size_t i = std::size_t(y0) * row; i < std::size_t(y1) * row; ++i)
        scaled.v[i] = std::max(floor_cd_m2, lr.v[i] + scale * (lt.v[i] - lr.v[i]));
    });
    PerceptualResult r;
    evaluate_luminance(scaled, lr, gaze_px, executor, r);
    it->second.push_back(r.p_max);
    for (const PerceptualRing& ring : r.rings) it->second.push_back(ring.p_max);
    return it->second;
  };
  // One bisection over log2(1 / m) on the largest P at index i.
  const auto multiple_of = [&](std::size_t i) {
    double lo = -kThresholdMultipleLog2Range, hi = kThresholdMultipleLog2Range;
    if (p_max_at(hi)[i] < 0.5) return 0.0;
    if (p_max_at(lo)[i] >= 0.5) return std::exp2(-lo);
    while (hi - lo > kThresholdMultipleLog2Tolerance) {
      const double mid = 0.5 * (lo + hi);
      (p_max_at(mid)[i] >= 0.5 ? hi : lo) = mid;
    }
    return std::exp2(-0.5 * (lo + hi));
  };
  const bool same = lt.v == lr.v;
  multiple = same ? 0.0 : multiple_of(0);
  if (ring_multiples == nullptr) return true;
  ring_multiples->clear();
  for (std::size_t r = 0; r < metrics::kRingCount; ++r) ring_multiples->push_back(same ? 0.0 : multiple_of(1 + r));
  return true;
}

void PerceptualMetric::evaluate_luminance(const Plane& test_cd_m2, const Plane& reference_cd_m2, glm::vec2 gaze_px,
                                          foveation::Executor* executor, PerceptualResult& out) const {
  const int w = test_cd_m2.width_px, h = test_cd_m2.height_px;
  const int levels = std::min(int(bands_.size()) / kBandsPerLevel, level_count(w, h));
  const std::shared_ptr<const GazeTables> gt = gaze_tables(gaze_px, w, h, levels, executor);
  const LaplacianPyramid pt = laplacian_pyramid(test_cd_m2, levels, executor);
  const LaplacianPyramid pr = laplacian_pyramid(reference_cd_m2, levels, executor);
  Plane acc, lum_column;
  for (int b = levels * kBandsPerLevel - 1; b >= 0; --b) {
    const std::size_t level = std::size_t(b / kBandsPerLevel);
    if (b % kBandsPerLevel == kBandsPerLevel - 1) lum_column = lum_columns(pr.mean[level], grid_, executor);
    BandEnergy be;
    band_energy({pt.band[std::size_t(b)], pr.band[std::size_t(b)], pr.mean[level], lum_column, gt->ecc_row[level],
                 gt->temporal_weight[level]},
                bands_[std::size_t(b)], grid_, executor, be);
    const auto& sigma = bands_[std::size_t(b)].pool_sigma_px;
    box3_blur(be.e_ach, sigma[0], executor);
    box3_blur(be.e_chr, sigma[1], executor);
    if (options_.masking) box3_blur(be.mask, sigma[0], executor);
    const bool same = !acc.v.empty() && acc.width_px == be.e_ach.width_px && acc.height_px == be.e_ach.height_px;
    const Plane up = acc.v.empty() || same ? Plane{} : pyramid_expand(acc, be.e_ach.width_px, be.e_ach.height_px, executor);
    combine_band(be, same ? &acc : up.v.empty() ? nullptr : &up, !same, options_.masking, executor);
    acc = std::move(be.e_ach);
  }
  out = PerceptualResult{};
  out.width_px = w;
  out.height_px = h;
  out.p_detect.resize(acc.v.size());
  const float log_half = float(std::log(0.5)), half_beta = float(0.5 * kPsychometricBeta);
  for_rows(executor, acc.height_px, [&](int y0, int y1) {
    for (std::size_t i = std::size_t(y0) * std::size_t(acc.width_px); i < std::size_t(y1) * std::size_t(acc.width_px); ++i)
      out.p_detect[i] = 0.0f - std::expm1(log_half * std::pow(std::max(0.0f, acc.v[i]), half_beta));
  });
  summarize(*gt, executor, out);
}

}  // namespace foveart::eval
