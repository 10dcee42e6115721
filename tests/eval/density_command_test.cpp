// `fovea-eval density` in process (bad options exit 2 naming the problem; a tiny sweep's rows,
// their verdicts, the smallest unseen ray fraction per kind, rays per point by contrast and both levers among them, and
// the content-aware row at eccentricity-only's detection) and the bisection it shares with
// the thesis check (eval/density_detection.hpp).
#include <eval/cmd_density.hpp>
#include <eval/density_detection.hpp>
#include <render_view/render_options.hpp>
#include <toolkit/image_io.hpp>

#include <engine/gltf_loader.hpp>
#include <foveation/display_model.hpp>

#include <CLI/CLI.hpp>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <vector>

#include "gltf_fixtures.hpp"  // engine_test::TempDir

using namespace foveart;

namespace {

int run_density_command(const eval::DensityOptions& o, std::string* out, std::string* err) {
  std::ostringstream os, es;
  const int code = eval::run_density(o, os, es);
  *out = os.str(), *err = es.str();
  return code;
}

eval::DensityOptions tiny_density(const std::string& cache) {
  eval::DensityOptions o;
  o.crop_px = glm::ivec2(96, 108);  // to 6 deg from the centre: scale 4 thins beyond 4
  o.render.rays_per_point = 2;
  o.render.threads = 2;
  o.render.cache_dir = cache;
  o.reference.spp = "16";
  o.scales = {1.0, 4.0};
  o.contrasts = {1.0};
  o.ray_contrasts = {1.0};
  o.both_contrasts = {1.0};
  o.render.density_scale = 4.0;  // the content-aware rows' scale: Poisson points to thin, or to give fewer rays
  return o;
}

}  // namespace

TEST(DensityCommand, BadOptionsExitTwoNamingTheProblem) {
  engine_test::TempDir dir;
  std::string out, err;
  eval::DensityOptions o = tiny_density(dir.path.string());
  o.reference.spp.clear();
  EXPECT_EQ(run_density_command(o, &out, &err), 2);
  EXPECT_NE(err.find("--reference-spp N is required"), std::string::npos) << err;
  o = tiny_density(dir.path.string());
  o.scales = {0.0};
  EXPECT_EQ(run_density_command(o, &out, &err), 2);
  EXPECT_NE(err.find("--scales"), std::string::npos) << err;
  o = tiny_density(dir.path.string());
  o.contrasts = {1.5};
  EXPECT_EQ(run_density_command(o, &out, &err), 2);
  EXPECT_NE(err.find("--contrasts"), std::string::npos) << err;
  o = tiny_density(dir.path.string());
  o.ray_contrasts = {0.0};
  EXPECT_EQ(run_density_command(o, &out, &err), 2);
  EXPECT_NE(err.find("--ray-contrasts"), std::string::npos) << err;
  o = tiny_density(dir.path.string());
  o.both_contrasts = {-1.0};
  EXPECT_EQ(run_density_command(o, &out, &err), 2);
  EXPECT_NE(err.find("--both-contrasts"), std::string::npos) << err;
  o = tiny_density(dir.path.string());
  o.rays_doublings = {0.0, 95.0};
  EXPECT_EQ(run_density_command(o, &out, &err), 2);
  EXPECT_NE(err.find("--rays-doublings"), std::string::npos) << err;
  o = tiny_density(dir.path.string());
  o.crop_px = glm::ivec2(5000, 36);
  EXPECT_EQ(run_density_command(o, &out, &err), 2);
  EXPECT_NE(err.find("--crop"), std::string::npos) << err;
  o = tiny_density(dir.path.string());
  o.render.out_prefix = (dir.path / "no_such_folder" / "tiny").string();
  EXPECT_EQ(run_density_command(o, &out, &err), 2) << "an output it cannot write fails before the sweep";
  EXPECT_NE(err.find("--out"), std::string::npos) << err;
  EXPECT_NE(err.find("no_such_folder"), std::string::npos) << err;
}

// A crop shows what the whole view shows there: "auto" exposure meters the preset's whole view.
// The control: the crop metered alone (the corridor end's bright wall) gets another exposure.
TEST(DensityCommand, ACropIsExposedAsTheWholeViewShowsIt) {
  engine_test::TempDir dir;
  eval::DensityOptions o = tiny_density(dir.path.string());
  o.scales = {1.0};
  o.contrasts.clear();
  o.ray_contrasts.clear();
  o.both_contrasts.clear();
  std::string out, err;
  ASSERT_EQ(run_density_command(o, &out, &err), 0) << err;
  const auto report = nlohmann::json::parse(out);
  const double exposure = report["exposure"].get<double>();

  engine::LoadResult loaded = engine::load_scene("default");
  ASSERT_TRUE(loaded.ok()) << loaded.error;
  const auto tracer = engine::Tracer::create(std::move(*loaded.scene));
  foveation::Executor executor(2);
  std::string error;
  render_view::RenderOptions whole;  // the fove preset's eye, as tiny_density's crop cuts from
  const auto whole_display =
      render_view::render_display(whole, *tracer, render_view::eye_view(whole, tracer->scene()), executor, &error);
  ASSERT_TRUE(whole_display) << error;
  EXPECT_DOUBLE_EQ(exposure, double(whole_display->exposure)) << "the JSON carries the float as it is";
  foveation::DisplayModel crop_display_model = *foveation::display_preset("fove");
  crop_display_model.width_px = o.crop_px->x;  // the eye's viewing distance, the crop's width
  render_view::RenderOptions crop = whole;
  crop.size_px = *o.crop_px;
  crop.fov.horizontal = crop_display_model.horizontal_fov_deg();
  // The report's frustum is the crop's, so that `fovea render --fov-deg L,R,U,D` renders the same view.
  EXPECT_NEAR(report["fov_deg"][1].get<double>() - report["fov_deg"][0].get<double>(), *crop.fov.horizontal, 1e-4);
  const auto crop_display =
      render_view::render_display(crop, *tracer, render_view::eye_view(crop, tracer->scene()), executor, &error);
  ASSERT_TRUE(crop_display) << error;
  EXPECT_NE(crop_display->exposure, whole_display->exposure) << "the control: metered alone, the crop differs";
}

TEST(DensityCommand, OutWritesEachMeasuredFrameBesideWhereTheMetricSeesIt) {
  engine_test::TempDir dir;
  eval::DensityOptions o = tiny_density(dir.path.string());
  o.contrasts = {1.0};
  o.ray_contrasts.clear();
  o.both_contrasts.clear();
  o.render.out_prefix = (dir.path / "tiny").string();
  std::string out, err;
  ASSERT_EQ(run_density_command(o, &out, &err), 0) << err;
  const auto j = nlohmann::json::parse(out);
  const auto expect_images = [&](const nlohmann::json& images, const std::string& name, const nlohmann::json& p_max) {
    ASSERT_EQ(images.size(), p_max.is_null() ? 1u : 2u) << images.dump();
    EXPECT_EQ(images[0], o.render.out_prefix + "_" + name + ".png");
    foveation::ImageRgb frame, p;
    std::string error;
    ASSERT_TRUE(toolkit::read_image(images[0], toolkit::PngValues::display, &frame, &error)) << error;
    EXPECT_EQ(frame.width_px, 96);
    EXPECT_EQ(frame.height_px, 108);
    if (p_max.is_null()) return;
    EXPECT_EQ(images[1], o.render.out_prefix + "_" + name + "_p.png");
    ASSERT_TRUE(toolkit::read_image(images[1], toolkit::PngValues::display, &p, &error)) << error;
    float brightest = 0.0f;
    for (const float v : p.rgb) brightest = std::max(brightest, v);
    EXPECT_NEAR(brightest, p_max.get<double>(), 0.5 / 255.0 + 1e-6) << name << ": the P map's brightest pixel is P max";
  };
  ASSERT_TRUE(j["full"]["images"].is_array()) << j["full"].dump();
  ASSERT_EQ(j["full"]["images"].size(), 3u);
  expect_images(nlohmann::json::array({j["full"]["images"][0]}), "reference", nullptr);
  expect_images(nlohmann::json::array({j["full"]["images"][1], j["full"]["images"][2]}), "full", j["full"]["p_max"]);
  ASSERT_EQ(j["rows"].size(), 3u);
  expect_images(j["rows"][0]["images"], "eccentricity_scale_1", j["rows"][0]["p_max"]);
  expect_images(j["rows"][1]["images"], "eccentricity_scale_4", j["rows"][1]["p_max"]);
  expect_images(j["rows"][2]["images"], "content_contrast_1", j["rows"][2]["p_max"]);
}

TEST(DensityCommand, RowsTheirVerdictsAndTheSmallestUnseenRayFraction) {
  engine_test::TempDir dir;
  std::string out, err;
  ASSERT_EQ(run_density_command(tiny_density(dir.path.string()), &out, &err), 0) << err;
  const auto j = nlohmann::json::parse(out);
  EXPECT_EQ(j["width"], 96);
  EXPECT_EQ(j["height"], 108);
  ASSERT_EQ(j["rows"].size(), 5u);  // two scales, one contrast, one rays-per-point contrast, one of both
  EXPECT_LT(j["rows"][1]["ray_fraction"].get<double>(), j["rows"][0]["ray_fraction"].get<double>()) << "scale 4 thins";
  EXPECT_EQ(j["rows"][3]["kind"], "rays");
  EXPECT_EQ(j["rows"][3]["content_rays"], 1.0);
  EXPECT_LT(j["rows"][3]["ray_fraction"].get<double>(), j["rows"][1]["ray_fraction"].get<double>())
      << "at scale 4, fewer rays per point in the flat and dark tiles";
  const auto& full = j["full"]["rings_p_max"];
  EXPECT_EQ(j["rows"][4]["kind"], "both");
  EXPECT_EQ(j["rows"][4]["content_contrast"], 1.0);
  EXPECT_EQ(j["rows"][4]["content_rays"], 1.0);
  EXPECT_LT(j["rows"][4]["ray_fraction"].get<double>(), j["rows"][3]["ray_fraction"].get<double>())
      << "thinning as well as fewer rays per point";
  for (const char* kind : {"eccentricity", "content", "rays", "both"}) {
    const nlohmann::json* smallest = nullptr;
    for (const auto& row : j["rows"]) {
      if (row["kind"] != kind) continue;
      bool unseen = true;  // every ring the full render does not show stays below one half
      for (std::size_t r = 0; r < full.size(); ++r)
        if (full[r].is_number() && full[r].get<double>() < 0.5 && row["rings_p_max"][r].get<double>() >= 0.5) unseen = false;
      EXPECT_EQ(row["unseen"].get<bool>(), unseen) << row.dump();
      if (unseen && (!smallest || row["ray_fraction"].get<double>() < (*smallest)["ray_fraction"].get<double>())) smallest = &row;
    }
    const auto& best = j[std::string("best_") + kind];
    if (smallest == nullptr) {
      EXPECT_TRUE(best.is_null()) << best.dump();
    } else {
      EXPECT_EQ(best, *smallest);
    }
  }
  // Same detection with the fewest rays: any content-aware kind, against eccentricity only at
  // the content-aware rows' scale (rows[1], scale 4), ring by ring.
  const auto p_of = [](const nlohmann::json& row) {
    std::vector<double> v;
    for (const auto& p : row["rings_p_max"]) v.push_back(p.is_null() ? std::nan("") : p.get<double>());
    return v;
  };
  ASSERT_EQ(j["rows"][1]["density_scale"], 4.0);
  const nlohmann::json* fewest = nullptr;
  for (const auto& row : j["rows"])
    if (row["kind"] != "eccentricity" && eval::detected_no_more(p_of(row), p_of(j["rows"][1])) &&
        (!fewest || row["ray_fraction"].get<double>() < (*fewest)["ray_fraction"].get<double>()))
      fewest = &row;
  if (fewest == nullptr) {
    EXPECT_TRUE(j["content_at_eccentricity_detection"].is_null()) << j["content_at_eccentricity_detection"].dump();
  } else {
    EXPECT_EQ(j["content_at_eccentricity_detection"], *fewest);
  }
}

// --content-at-unseen: the content-aware rows also thin from the sparsest density nobody sees
// (eccentricity only's smallest unseen ray fraction); "same detection" stays at --density-scale.
TEST(DensityCommand, ContentAtUnseenAlsoThinsFromTheSparsestUnseenScale) {
  engine_test::TempDir dir;
  eval::DensityOptions o = tiny_density(dir.path.string());
  o.scales = {1.0, 2.0, 4.0};
  o.ray_contrasts.clear();
  o.both_contrasts.clear();
  o.render.density_scale = 2.0;
  o.content_at_unseen = true;
  std::string out, err;
  ASSERT_EQ(run_density_command(o, &out, &err), 0) << err;
  const auto j = nlohmann::json::parse(out);
  ASSERT_FALSE(j["best_eccentricity"].is_null()) << "the tiny view has a density the metric does not see";
  const double unseen = j["best_eccentricity"]["density_scale"].get<double>();
  ASSERT_NE(unseen, o.render.density_scale) << "the control: not --density-scale";
  EXPECT_EQ(j["content_density_scales"], nlohmann::json::array({o.render.density_scale, unseen}));
  ASSERT_EQ(j["rows"].size(), 5u);
  for (const int i : {3, 4}) EXPECT_EQ(j["rows"][i]["kind"], "content") << i;
  EXPECT_EQ(j["rows"][3]["density_scale"].get<double>(), o.render.density_scale);
  EXPECT_EQ(j["rows"][4]["density_scale"].get<double>(), unseen);
  const auto p_of = [](const nlohmann::json& row) {
    std::vector<double> v;
    for (const auto& p : row["rings_p_max"]) v.push_back(p.is_null() ? std::nan("") : p.get<double>());
    return v;
  };
  ASSERT_EQ(j["rows"][1]["density_scale"].get<double>(), o.render.density_scale);
  const bool same = eval::detected_no_more(p_of(j["rows"][3]), p_of(j["rows"][1]));
  EXPECT_EQ(j["content_at_eccentricity_detection"], same ? j["rows"][3] : nlohmann::json())
      << "judged at --density-scale only: " << out;

  o.content_at_unseen = false;
  ASSERT_EQ(run_density_command(o, &out, &err), 0) << err;
  const auto without = nlohmann::json::parse(out);
  EXPECT_EQ(without["content_density_scales"], nlohmann::json::array({o.render.density_scale}));
  EXPECT_EQ(without["rows"].size(), 4u);
}

// --rays-doublings: a rays row per contrast and doubling eccentricity, each naming its doubling;
// the contrast doubling every 2 degrees (steps inside the 6-degree crop) casts fewer rays than
// the same contrast everywhere. Without the list, --content-rays-doubling's one value.
TEST(DensityCommand, RaysDoublingsGiveARaysRowEach) {
  engine_test::TempDir dir;
  eval::DensityOptions o = tiny_density(dir.path.string());
  o.scales = {4.0};
  o.contrasts.clear();
  o.both_contrasts.clear();
  o.ray_contrasts = {0.25};
  o.rays_doublings = {0.0, 2.0};
  std::string out, err;
  ASSERT_EQ(run_density_command(o, &out, &err), 0) << err;
  auto j = nlohmann::json::parse(out);
  ASSERT_EQ(j["rows"].size(), 3u);
  EXPECT_EQ(j["rows"][1]["kind"], "rays");
  EXPECT_EQ(j["rows"][1]["content_rays_doubling_deg"], 0.0);
  EXPECT_EQ(j["rows"][2]["kind"], "rays");
  EXPECT_EQ(j["rows"][2]["content_rays_doubling_deg"], 2.0);
  EXPECT_LT(j["rows"][2]["ray_fraction"].get<double>(), j["rows"][1]["ray_fraction"].get<double>());

  o.rays_doublings.clear();
  o.render.content_rays_doubling_deg = 2.0;
  ASSERT_EQ(run_density_command(o, &out, &err), 0) << err;
  j = nlohmann::json::parse(out);
  ASSERT_EQ(j["rows"].size(), 2u);
  EXPECT_EQ(j["rows"][1]["content_rays_doubling_deg"], 2.0);
}

// On the command line, --contrasts with no value leaves the thinning rows out; with a value
// (the control) there is one.
TEST(DensityCommand, ContrastsAloneOnTheCommandLineMeansNone) {
  engine_test::TempDir dir;
  for (const bool none : {true, false}) {
    std::vector<std::string> args;
    std::istringstream words(
        "fovea-eval density --json --crop=96x108 --rays-per-point=2 --threads=2 --reference-spp=16 --scales=4 "
        "--density-scale=4 --ray-contrasts=1 --contrasts");
    for (std::string word; words >> word;) args.push_back(word);
    if (!none) args.emplace_back("1");
    args.push_back("--cache-dir=" + dir.path.string());
    std::vector<const char*> argv;
    for (const std::string& a : args) argv.push_back(a.c_str());
    CLI::App app;
    eval::register_density(app);
    testing::internal::CaptureStdout();
    testing::internal::CaptureStderr();
    EXPECT_NO_THROW(app.parse(int(argv.size()), argv.data())) << (none ? "--contrasts alone" : "--contrasts 1");
    const std::string out = testing::internal::GetCapturedStdout();
    testing::internal::GetCapturedStderr();
    const auto j = nlohmann::json::parse(out);
    std::size_t content_rows = 0;
    for (const auto& row : j["rows"]) content_rows += row["kind"] == "content" ? 1 : 0;
    EXPECT_EQ(content_rows, none ? 0u : 1u) << out;
    EXPECT_EQ(j["rows"].back()["kind"], "rays");
  }
}

// --ring-multiples: every row and the full render say how many times above threshold each ring
// is: above 1 where its largest P reaches one half, none where the ring has no pixels.
TEST(DensityCommand, RingMultiplesAgreeWithEachRingsDetection) {
  engine_test::TempDir dir;
  eval::DensityOptions o = tiny_density(dir.path.string());
  o.scales = {4.0};
  o.contrasts.clear();
  o.ray_contrasts.clear();
  o.both_contrasts.clear();
  std::string out, err;
  ASSERT_EQ(run_density_command(o, &out, &err), 0) << err;
  EXPECT_FALSE(nlohmann::json::parse(out)["rows"][0].contains("rings_threshold_multiple")) << "not asked for";
  o.ring_multiples = true;
  ASSERT_EQ(run_density_command(o, &out, &err), 0) << err;
  const auto j = nlohmann::json::parse(out);
  int compared = 0;
  for (const auto* row : {&j["full"], &j["rows"][0]}) {
    const auto& p = (*row)["rings_p_max"];
    const auto& m = (*row)["rings_threshold_multiple"];
    ASSERT_EQ(m.size(), p.size()) << row->dump();
    for (std::size_t r = 0; r < p.size(); ++r) {
      ASSERT_EQ(m[r].is_null(), p[r].is_null()) << "ring " << r << ": " << row->dump();
      if (p[r].is_null() || std::abs(p[r].get<double>() - 0.5) < 0.02) continue;  // at one half: the bisection's
      EXPECT_EQ(m[r].get<double>() >= 1.0, p[r].get<double>() >= 0.5) << "ring " << r << ": " << row->dump();
      ++compared;
    }
  }
  EXPECT_GE(compared, 4) << out;
}

TEST(DensityDetection, BisectionFindsTheHalfCrossingOrSaysThereIsNone) {
  int calls = 0;
  const auto step_at_1_3 = [&](double s) -> std::optional<double> { return ++calls, s < 1.3 ? 0.2 : 0.9; };
  const std::optional<double> s = eval::half_detection_scale(step_at_1_3, 1.0, 3.0, 0.01);
  ASSERT_TRUE(s.has_value());
  EXPECT_NEAR(*s, 1.3, 0.01);
  EXPECT_LE(calls, 2 + 8);  // the ends and log2(2 / 0.01) halvings
  EXPECT_FALSE(eval::half_detection_scale(step_at_1_3, 1.5, 3.0, 0.01)) << "detected at both ends";
  EXPECT_FALSE(eval::half_detection_scale(step_at_1_3, 1.0, 1.2, 0.01)) << "unseen at both ends";
  EXPECT_FALSE(eval::half_detection_scale([](double) { return std::optional<double>(); }, 1.0, 3.0, 0.01));
}
