// The thesis check (thesis 6.3, Table 3): the density scale at which the perceptual metric
// predicts 50 % detection of foveation (the image's largest P, eval/density_detection.hpp) for
// NN, MSM and RBF (k = 5) at the thesis preset, on the built-in scene's dark pillars against the
// lit corridor end, against the user study's 50 % scales. Bisection over the density scale.
//
// The view: the centre 256x256 crop of the thesis view at its own pixels per degree (19 at the
// gaze, D = 0.85 x 1280 px), the gaze at its centre: eccentricities to 9.4 deg, where the thesis's
// density first thins (from 7.2 deg / scale). Rays per point: 128, not the thesis's 32: the thesis
// sampled a cubemap, a point's colour was the texture's, while 32 jittered rays through geometry
// leave edge noise the metric detects in the full render itself (P 0.98 against the reference);
// at 128 the full render stays below 0.5 (checked below), so what the metric sees is foveation's.
// The fovea: the pixel grid (the project's default) where the thesis's density is one point per
// pixel or more; the thesis's Poisson fovea under nearest-neighbour aliases sub-pixel edges, which
// the metric detects at every scale of the study, 1 to 3 (docs/lab/perceptual_metric.md).
// The control: the metric without its eccentricity term must predict detection at a density the
// metric still passes (a lower scale).
//
// Why it misses Table 3 (docs/lab/perceptual_metric.md, "The thesis check"): every method crosses
// where the first Poisson points enter the crop's corners (7.2 deg / scale = 9.4 deg), so the
// crossing is the crop's geometry, asserted below: the metric sees the one-pixel jaggies of a
// high-contrast edge rebuilt from Poisson points at any eccentricity of the crop. The study's
// subjects judged "anything unnatural" with no reference beside them (thesis 6.2) and reported
// trembling edges (thesis 6.3), a temporal effect: the metric's flicker option brackets the study
// between a gaze that steps (seen at every scale) and one that jitters every frame (seen from about
// scale 3), bench/thesis_check.sh; predicting 1.75 needs the study's gaze statistics. The test
// asserts the bracket at the study's scale: a one-pixel gaze move seen at 10 Hz, unseen at 35 Hz.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <numbers>
#include <optional>
#include <tuple>
#include <utility>

#include <eval/density_detection.hpp>
#include <eval/reference.hpp>
#include <foveation/display_model.hpp>
#include <metrics/image_metrics.hpp>

#include <engine/gltf_loader.hpp>
#include <engine/render.hpp>

#include "under_sanitizer.hpp"

namespace {

using namespace foveart;

constexpr int kCropPx = 256;
constexpr int kRaysPerPoint = 128;
constexpr double kScaleLo = 0.5, kScaleHi = 3.0;  // the user study's range was 1-3
constexpr double kScaleTolerance = 0.1;
constexpr double kThesisViewDistancePx = 0.85 * 1280.0;  // the thesis preset's D (display_model.cpp)

// The density scale from which Poisson points replace the pixel grid somewhere in the crop: the
// grid reaches pixel_grid_ecc_deg / scale (thesis eqs. 2-3), the crop's corner lies at e(corner).
double first_poisson_scale() {
  const double grid_ecc_deg = foveation::pixel_grid_ecc_deg(foveation::display_nyquist_cpd(kThesisViewDistancePx));
  return grid_ecc_deg / foveation::eccentricity_deg(std::hypot(0.5 * kCropPx, 0.5 * kCropPx), kThesisViewDistancePx);
}

struct Table3Row {
  const char* method;
  double mean, sd;
};
constexpr Table3Row kTable3[] = {{"nearest", 1.751, 0.350}, {"msm", 1.675, 0.248}, {"rbf", 1.779, 0.362}};

// The scene, the crop's view, its converged reference and the metric with and without the
// eccentricity term, built once for the suite.
struct ThesisView {
  std::unique_ptr<engine::Tracer> tracer;
  foveation::Executor executor{2};
  render_view::RenderOptions options;
  FoveartEyeView view{};
  glm::vec2 gaze{kCropPx / 2.0f, kCropPx / 2.0f};
  foveation::ImageRgb reference;
  eval::PerceptualMetric metric, control;
  eval::PerceptualMetric flicker_10hz, flicker_35hz;  // the metric for a change that flickers
  std::string error;
  std::map<std::tuple<const eval::PerceptualMetric*, std::string, double>, eval::DensityDetection> measurements;

  ThesisView() {
    engine::LoadResult loaded = engine::load_scene("default");
    const std::uint64_t hash = eval::scene_content_hash(*loaded.scene);
    tracer = engine::Tracer::create(std::move(*loaded.scene));
    options.preset = "thesis";
    // The whole view's exposure (a crop of it would meter only the crop).
    const FoveartEyeView whole = render_view::eye_view(options, tracer->scene());
    const auto display = render_view::render_display(options, *tracer, whole, executor, &error);
    if (!display) return;
    const double view_distance_px = kThesisViewDistancePx;
    options.size_px = glm::ivec2(kCropPx, kCropPx);
    options.fov.horizontal = 2.0 * std::atan(0.5 * kCropPx / view_distance_px) * 180.0 / std::numbers::pi;
    options.rays_per_point = kRaysPerPoint;
    options.pattern = "pixel-grid";
    view = render_view::eye_view(options, tracer->scene());
    eval::ReferenceOptions ro;
    ro.spp = 8 * kRaysPerPoint;
    ro.cache_dir = FOVEART_TEST_CACHE_DIR;
    const auto ref = eval::converged_reference(&foveart_engine_trace_rays, tracer.get(), hash, view, gaze, ro, executor,
                                               {}, &error);
    if (!ref) return;
    reference = ref->image;
    eval::PerceptualDisplay pd = eval::view_display(metrics::eccentricity_map(view, gaze), eval::Eye::kLeft);
    pd.transform = *display;
    if (!eval::PerceptualMetric::create(pd, kCropPx, kCropPx, {}, metric, error, &executor)) return;
    eval::PerceptualOptions off;
    off.eccentricity = eval::EccentricityTerm::kOff;
    if (!eval::PerceptualMetric::create(pd, kCropPx, kCropPx, off, control, error, &executor)) return;
    for (auto [hz, m] : {std::pair{10.0, &flicker_10hz}, std::pair{35.0, &flicker_35hz}}) {
      eval::PerceptualOptions flicker;
      flicker.temporal_freq_hz = hz;
      if (!eval::PerceptualMetric::create(pd, kCropPx, kCropPx, flicker, *m, error, &executor)) return;
    }
    error.clear();
  }

  eval::DensityProbe probe(const char* method, const eval::PerceptualMetric& m) {
    eval::DensityProbe p;
    p.tracer = tracer.get();
    p.view = view;
    p.gaze_px = gaze;
    p.options = options;
    p.options.interpolation = method;
    p.options.k = std::string(method) == "nearest" ? 0 : 5;
    p.reference = &reference;
    p.metric = &m;
    p.cache_dir = std::filesystem::path(FOVEART_TEST_CACHE_DIR);
    p.executor = &executor;
    return p;
  }

  // One density scale's measurement, each (metric, method, scale) once: the control row reads
  // the scale the bracket measured below the crossing.
  const eval::DensityDetection* measured(const eval::DensityProbe& p, double scale) {
    const auto key = std::make_tuple(p.metric, p.options.interpolation, scale);
    if (const auto it = measurements.find(key); it != measurements.end()) return &it->second;
    eval::DensityDetection d;
    if (!eval::measure_density(p, scale, 0.0, &d, &error)) return nullptr;
    return &measurements.emplace(key, std::move(d)).first->second;
  }

  // The image's largest P at one density scale (nullopt on an error).
  std::optional<double> detection(const eval::DensityProbe& p, double scale) {
    const eval::DensityDetection* d = measured(p, scale);
    if (d == nullptr) return std::nullopt;
    std::printf("  %s scale %.3f: rays %.3f of the full render's, P max %.3f\n", p.options.interpolation.c_str(), scale,
                d->ray_fraction, eval::detection_probability(d->p));
    return eval::detection_probability(d->p);
  }

  // The scale where the image's largest P crosses 0.5 (nullopt: no crossing in range, or an error).
  std::optional<double> half_scale(const eval::DensityProbe& p) {
    return eval::half_detection_scale([&](double scale) { return detection(p, scale); }, kScaleLo, kScaleHi,
                                      kScaleTolerance);
  }

  // The sanitizer builds check memory, not the numbers a second time: two measurements in place
  // of the bisection's seven. P under 0.5 one tolerance below `expected` and at or over it one
  // above puts the crossing within the tolerance of `expected`, as the bisection's assertion
  // does; nullopt otherwise.
  std::optional<double> bracketed_half_scale(const eval::DensityProbe& p, double expected) {
    const std::optional<double> below = detection(p, expected - kScaleTolerance);
    const std::optional<double> above = detection(p, expected + kScaleTolerance);
    if (!below || !above || *below >= 0.5 || *above < 0.5) return std::nullopt;
    return expected;
  }
};

ThesisView& thesis_view() {
  static ThesisView v;
  return v;
}

std::string scale_text(const std::optional<double>& s) {
  if (!s) return "none in range";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2f", *s);
  return buf;
}

}  // namespace

TEST(ThesisDensity, HalfDetectionScalesAgainstTable3) {
  ThesisView& v = thesis_view();
  ASSERT_TRUE(v.error.empty()) << v.error;
  // The measurement discriminates: the full render at these rays per pixel is not detected.
  engine::RenderSettings rs;
  rs.spp = kRaysPerPoint;
  foveation::ImageRgb full;
  ASSERT_EQ(engine::render_full(&foveart_engine_trace_rays, v.tracer.get(), v.view, rs, &full, v.executor).status,
            FOVEART_RESULT_SUCCESS);
  eval::PerceptualResult baseline;
  ASSERT_TRUE(v.metric.evaluate(full, v.reference, v.gaze, &v.executor, baseline, v.error)) << v.error;
  std::printf("full render at %d rays per pixel against the reference: P max %.3f\n", kRaysPerPoint, baseline.p_max);
  ASSERT_LT(baseline.p_max, 0.5) << "the full render's own noise is detected: the check cannot see foveation";

  std::vector<std::optional<double>> found;
  const std::size_t methods = test::kUnderSanitizer ? 1 : std::size(kTable3);  // NN only under the sanitizers
  for (std::size_t i = 0; i < methods; ++i) {
    const eval::DensityProbe probe = v.probe(kTable3[i].method, v.metric);
    found.push_back(test::kUnderSanitizer ? v.bracketed_half_scale(probe, first_poisson_scale()) : v.half_scale(probe));
    ASSERT_TRUE(v.error.empty()) << v.error;
  }
  ASSERT_TRUE(found[0]) << "nearest: no crossing of one half in " << kScaleLo << "-" << kScaleHi;
  // The control, at the densest scale the bisection saw the metric pass (within the tolerance below the crossing).
  const double control_scale = *found[0] - kScaleTolerance;
  const eval::DensityDetection* control_measured = v.measured(v.probe("nearest", v.control), control_scale);
  ASSERT_NE(control_measured, nullptr) << v.error;
  const eval::DensityDetection* metric_measured = v.measured(v.probe("nearest", v.metric), control_scale);
  ASSERT_NE(metric_measured, nullptr) << v.error;
  const eval::DensityDetection& at_control = *control_measured;
  const eval::DensityDetection& at_metric = *metric_measured;
  std::printf("\n| method | scale at P = 0.5 | thesis mean +- SD | within 1 SD |\n|---|---|---|---|\n");
  for (std::size_t i = 0; i < found.size(); ++i) {
    const Table3Row& t = kTable3[i];
    const bool within = found[i] && std::abs(*found[i] - t.mean) <= t.sd;
    std::printf("| %s | %s | %.2f +- %.2f | %s |\n", t.method, scale_text(found[i]).c_str(), t.mean, t.sd,
                within ? "pass" : "MISS");
  }
  std::printf("| nearest, control without the eccentricity term | below %.2f (P max %.3f there; the metric's %.3f) | "
              "%.2f +- %.2f | %s |\n",
              control_scale, eval::detection_probability(at_control.p), eval::detection_probability(at_metric.p),
              kTable3[0].mean, kTable3[0].sd, control_scale < kTable3[0].mean - kTable3[0].sd ? "MISS" : "-");

  // What holds: every method crosses one half inside the range, and they agree with each other as
  // the user study's did (thesis Table 4: no significant difference) to within its smallest SD.
  for (std::size_t i = 0; i < found.size(); ++i) ASSERT_TRUE(found[i]) << kTable3[i].method;
  // What stands in the way: each crosses where the first Poisson points enter the crop.
  std::printf("the first Poisson points enter the crop at scale %.3f\n", first_poisson_scale());
  for (std::size_t i = 0; i < found.size(); ++i)
    EXPECT_NEAR(*found[i], first_poisson_scale(), kScaleTolerance) << kTable3[i].method;
  const auto [lo, hi] = std::minmax_element(found.begin(), found.end());
  EXPECT_LE(**hi - **lo, kTable3[1].sd) << "the methods' scales spread wider than the user study's SD";
  // The eccentricity term is what lets the density thin: without it the metric detects foveation
  // at a density the metric does not.
  EXPECT_LT(eval::detection_probability(at_metric.p), 0.5);
  EXPECT_GE(eval::detection_probability(at_control.p), 0.5) << "the control does not see the periphery's thinning sooner";

  // The study without a reference (thesis 6.2: the subjects looked for anything unnatural): what
  // changes between two frames whose gaze differs by a pixel, at the study's NN scale. Through
  // castleCSF's temporal channels the change is seen near 10 Hz (the transient channel's peak at
  // these luminances, which one step of the gaze drives) and unseen at 35 Hz (a gaze estimate that
  // jitters every frame of the FOVE 0's 70 Hz): the two temporal readings of the task bracket the
  // study's 50 % scale, which one of them alone does not predict (bench/thesis_check.sh).
  foveation::ImageRgb frames[2];
  for (int i = 0; i < 2; ++i) {
    eval::DensityProbe p = v.probe("nearest", v.metric);
    p.gaze_px.x += float(i);
    p.keep_image = true;
    eval::DensityDetection d;
    ASSERT_TRUE(eval::measure_density(p, kTable3[0].mean, 0.0, &d, &v.error)) << v.error;
    frames[i] = std::move(d.image);
  }
  ASSERT_NE(frames[0].rgb, frames[1].rgb) << "the gaze move changed nothing: no Poisson point in the crop";
  eval::PerceptualResult stepped, jittering;
  ASSERT_TRUE(v.flicker_10hz.evaluate(frames[1], frames[0], v.gaze, &v.executor, stepped, v.error)) << v.error;
  ASSERT_TRUE(v.flicker_35hz.evaluate(frames[1], frames[0], v.gaze, &v.executor, jittering, v.error)) << v.error;
  std::printf("scale %.3f, gaze moved one pixel: P max %.3f at 10 Hz, %.3f at 35 Hz\n", kTable3[0].mean, stepped.p_max,
              jittering.p_max);
  EXPECT_GE(stepped.p_max, 0.5);
  EXPECT_LT(jittering.p_max, 0.5);
}
