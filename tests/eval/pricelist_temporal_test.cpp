// The price list's temporal columns: a tiny sweep over the built-in motion
// reports per-ring flicker and error for off / restart / image / rays of every
// setting with history, agrees between JSON and CSV, resumes without measuring again;
// bad temporal options are errors naming the option; the acceptance reads the
// ratios it reports.
#include "gltf_fixtures.hpp"

#include <eval/cmd_pricelist.hpp>
#include <eval/pricelist_temporal_report.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <sstream>

namespace fs = std::filesystem;
using namespace foveart;
using Json = nlohmann::ordered_json;

namespace {

eval::PricelistOptions tiny(const fs::path& out) {
  eval::PricelistOptions o;
  o.size_px = glm::ivec2(48, 54);
  o.out_dir = out.string();
  o.reference_spp = "16";
  o.frames = 1;
  o.history_frames = 2;
  o.threads = 2;
  o.grid.full_rays_per_point = {1};
  o.grid.interpolation = {"nearest:1", "msm:5"};
  o.grid.density_scale = {1.0};
  o.grid.rays_per_point = {1};
  o.grid.pattern = {"pixel-grid"};
  o.grid.history_rays_per_point = {1};
  o.grid.content_contrast.clear();  // rows without history: no tracks of their own
  o.grid.content_rays.clear();
  o.temporal.size_px = glm::ivec2(64, 72);
  o.temporal.frames = 4;
  o.temporal.start_s = 0.5;
  o.temporal.reference_spp = 8;
  return o;
}

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream in(line);
  std::string c;
  while (std::getline(in, c, ',')) cells.push_back(c);
  if (!line.empty() && line.back() == ',') cells.emplace_back();
  return cells;
}

// A temporal JSON with one setting's three tracks: flicker and PSNR per ring as given.
Json synthetic(const std::array<double, 7>& off_flicker, const std::array<double, 7>& reproject_flicker,
               const std::array<double, 7>& off_psnr, const std::array<double, 7>& reproject_psnr) {
  const auto track = [](const std::string& id, const std::array<double, 7>& f, const std::array<double, 7>& p) {
    Json rings = Json::array();
    for (std::size_t r = 0; r < 7; ++r) rings.push_back({{"flicker", f[r]}, {"psnr", p[r]}});
    return Json{{"id", id}, {"temporal", id.substr(id.rfind('-') + 1)}, {"rings", rings}};
  };
  Json t = {{"run", {{"motion", "builtin"}, {"frames", 36}, {"start_s", 1.3}, {"fps", 70.0}, {"width", 320},
                     {"height", 360}}},
            {"tracks", Json::array()}};
  t["tracks"].push_back(track("s_temporal-off", off_flicker, off_psnr));
  t["tracks"].push_back(track("s_temporal-restart", off_flicker, off_psnr));
  t["tracks"].push_back(track("s_temporal-image", reproject_flicker, reproject_psnr));
  return t;
}

}  // namespace

TEST(PricelistTemporal, TinySweepReportsEveryTemporalVariantPerRingAndResumes) {
  engine_test::TempDir dir;
  const eval::PricelistOptions o = tiny(dir.path / "pl");
  std::ostringstream out, err;
  ASSERT_EQ(eval::run_pricelist(o, out, err), 0) << err.str();
  EXPECT_NE(out.str().find("the image history flickers"), std::string::npos) << out.str();
  std::ifstream jf(dir.path / "pl" / "pricelist.json");
  const Json doc = Json::parse(jf);
  const Json& t = doc["temporal"];
  ASSERT_TRUE(t.is_object());
  EXPECT_EQ(t["run"]["frames"], 4);
  EXPECT_EQ(t["run"]["width"], 64);
  EXPECT_EQ(t["reference"]["spp"], 8);
  ASSERT_EQ(t["tracks"].size(), 9u);  // full_spp1 + 2 settings x off/restart/reproject/cache
  const std::vector<std::string> ids = {"full_spp1",
                                        "nearest_k1_s1_pixel-grid_r1_temporal-off",
                                        "nearest_k1_s1_pixel-grid_r1_temporal-restart",
                                        "nearest_k1_s1_pixel-grid_r1_temporal-image",
                                        "nearest_k1_s1_pixel-grid_r1_temporal-rays",
                                        "msm_k5_s1_pixel-grid_r1_temporal-off",
                                        "msm_k5_s1_pixel-grid_r1_temporal-restart",
                                        "msm_k5_s1_pixel-grid_r1_temporal-image",
                                        "msm_k5_s1_pixel-grid_r1_temporal-rays"};
  // Where each of the acceptance's setting's tracks sits.
  constexpr std::size_t kOff = 5, kReproject = 7, kCache = 8;
  for (std::size_t i = 0; i < ids.size(); ++i) {
    const Json& tr = t["tracks"][i];
    EXPECT_EQ(tr["id"], ids[i]);
    ASSERT_EQ(tr["rings"].size(), 7u);
    for (const Json& r : tr["rings"]) {
      EXPECT_TRUE(r["flicker"].is_number()) << ids[i] << " " << r.dump();
      EXPECT_TRUE(r["flicker_tracked"].is_number()) << ids[i] << " " << r.dump();
      EXPECT_TRUE(r["psnr"].is_number()) << ids[i] << " " << r.dump();
    }
  }
  for (std::size_t r = 0; r < 7; ++r) {  // the controls, measured like a track
    const Json& ring = t["reference"]["rings"][r];
    for (const char* history : {"sample_history", "sample_history_kept", "ray_cache", "ray_cache_kept"}) {
      EXPECT_GT(ring[std::string(history) + "_flicker"].get<double>(), 0.0) << history << " " << ring.dump();
      EXPECT_GT(ring[std::string(history) + "_flicker_tracked"].get<double>(), 0.0) << history << " " << ring.dump();
      EXPECT_TRUE(ring[std::string(history) + "_psnr"].is_number()) << history << " " << ring.dump();
    }
    EXPECT_GT(ring["stable_blur_flicker"].get<double>(), 0.0) << ring.dump();
    EXPECT_GT(ring["stable_blur_flicker_tracked"].get<double>(), 0.0) << ring.dump();
    EXPECT_TRUE(ring["stable_blur_psnr"].is_number()) << ring.dump();
    EXPECT_GT(ring["history_on_reference_flicker"].get<double>(), 0.0) << ring.dump();
    EXPECT_GT(ring["history_on_reference_flicker_tracked"].get<double>(), 0.0) << ring.dump();
    // Fed the reference instead of 1-ray frames, the same history errs less than the reprojecting track.
    EXPECT_GT(ring["history_on_reference_psnr"].get<double>(),
              t["tracks"][kReproject]["rings"][r]["psnr"].get<double>())
        << ring.dump();
  }
  // The track names the still setting it belongs to: off is the setting without history.
  EXPECT_EQ(t["tracks"][1]["setting"], "nearest_k1_s1_pixel-grid_r1");
  EXPECT_EQ(t["tracks"][3]["setting"], "nearest_k1_s1_pixel-grid_r1_image");
  EXPECT_EQ(t["tracks"][4]["setting"], "nearest_k1_s1_pixel-grid_r1_image");
  EXPECT_EQ(t["tracks"][kCache]["temporal"], "rays");
  EXPECT_EQ(t["tracks"][kCache]["temporal_reset_frames"], t["tracks"][kReproject]["temporal_reset_frames"]);
  // The acceptance is read at the layer's defaults (MSM k = 5, scale 1, pixel grid, 1 ray).
  EXPECT_EQ(t["acceptance"]["setting"], "msm_k5_s1_pixel-grid_r1");
  ASSERT_EQ(t["acceptance"]["flicker_ratio_off_over_image"].size(), 7u);
  const double ratio = t["acceptance"]["flicker_ratio_off_over_image"][4].get<double>();
  EXPECT_NEAR(ratio,
              t["tracks"][kOff]["rings"][4]["flicker"].get<double>() /
                  t["tracks"][kReproject]["rings"][4]["flicker"].get<double>(),
              1e-12);
  const double tracked_ratio = t["acceptance"]["flicker_tracked_ratio_off_over_image"][4].get<double>();
  EXPECT_NEAR(tracked_ratio,
              t["tracks"][kOff]["rings"][4]["flicker_tracked"].get<double>() /
                  t["tracks"][kReproject]["rings"][4]["flicker_tracked"].get<double>(),
              1e-12);
  EXPECT_NEAR(t["acceptance"]["flicker_ratio_off_over_stable_blur"][4].get<double>(),
              t["tracks"][kOff]["rings"][4]["flicker"].get<double>() /
                  t["reference"]["rings"][4]["stable_blur_flicker"].get<double>(),
              1e-12);
  EXPECT_NEAR(t["acceptance"]["flicker_tracked_ratio_off_over_history_on_reference"][4].get<double>(),
              t["tracks"][kOff]["rings"][4]["flicker_tracked"].get<double>() /
                  t["reference"]["rings"][4]["history_on_reference_flicker_tracked"].get<double>(),
              1e-12);
  EXPECT_NEAR(t["acceptance"]["flicker_ratio_off_over_sample_history"][4].get<double>(),
              t["tracks"][kOff]["rings"][4]["flicker"].get<double>() /
                  t["reference"]["rings"][4]["sample_history_flicker"].get<double>(),
              1e-12);
  EXPECT_TRUE(t["acceptance"]["peripheral_tracked_flicker_5x_lower"].is_boolean());
  // The render cache's goal reads its own track against the same off.
  const Json& cache_goal = t["acceptance"]["render_cache"];
  EXPECT_NEAR(cache_goal["flicker_tracked_ratio"][4].get<double>(),
              t["tracks"][kOff]["rings"][4]["flicker_tracked"].get<double>() /
                  t["tracks"][kCache]["rings"][4]["flicker_tracked"].get<double>(),
              1e-12);
  EXPECT_NEAR(cache_goal["psnr_minus_off_db"][0].get<double>(),
              t["tracks"][kCache]["rings"][0]["psnr"].get<double>() - t["tracks"][kOff]["rings"][0]["psnr"].get<double>(),
              1e-12);
  EXPECT_TRUE(cache_goal["peripheral_flicker_5x_lower"].is_boolean());
  EXPECT_NE(out.str().find("The render cache"), std::string::npos) << out.str();
  EXPECT_EQ(t["sanity"]["flicker_margin_db"].size(), 7u);

  // temporal.csv: one row per track, the same numbers as the JSON.
  std::ifstream csv(dir.path / "pl" / "temporal.csv");
  std::string line;
  std::getline(csv, line);
  const std::vector<std::string> header = split(line);
  const auto col = std::find(header.begin(), header.end(), "flicker_20-30") - header.begin();
  ASSERT_LT(std::size_t(col), header.size());
  std::size_t rows = 0;
  while (std::getline(csv, line)) {
    const std::vector<std::string> cells = split(line);
    ASSERT_EQ(cells.size(), header.size()) << line;
    EXPECT_EQ(cells[0], ids[rows]);
    EXPECT_NEAR(std::stod(cells[std::size_t(col)]), t["tracks"][rows]["rings"][4]["flicker"].get<double>(), 1e-12);
    ++rows;
  }
  EXPECT_EQ(rows, ids.size());
  std::ifstream md(dir.path / "pl" / "report.md");
  std::ostringstream report;
  report << md.rdbuf();
  EXPECT_NE(report.str().find("## Temporal columns"), std::string::npos);
  // Frame by frame: both pictures, and the settled frames (none in a 4-frame window: no ratio).
  EXPECT_NE(report.str().find("### Frame by frame in the periphery"), std::string::npos);
  for (const char* png : {eval::kTemporalPlotFixed, eval::kTemporalPlotTracked}) {
    EXPECT_GT(fs::file_size(dir.path / "pl" / png), 1000u) << png;
    EXPECT_NE(report.str().find(png), std::string::npos) << png;
  }
  EXPECT_EQ(t["reference"]["settled_frames"], 0);
  EXPECT_EQ(t["acceptance"]["settled_periphery"]["frames"], 0);
  EXPECT_TRUE(t["acceptance"]["settled_periphery"]["flicker_ratio_off_over_image"].is_null());
  EXPECT_EQ(t["tracks"][kReproject]["bands"][1]["flicker_by_frame"].size(), 4u);
  EXPECT_EQ(t["tracks"][kCache]["bands"][1]["flicker_by_frame"].size(), 4u);
  EXPECT_NE(report.str().find("The render cache"), std::string::npos);

  // Resume: nothing is measured again, the same numbers come back.
  std::ostringstream out2, err2;
  ASSERT_EQ(eval::run_pricelist(o, out2, err2), 0) << err2.str();
  EXPECT_NE(err2.str().find("2 already measured"), std::string::npos) << err2.str();
  std::ifstream jf2(dir.path / "pl" / "pricelist.json");
  EXPECT_EQ(Json::parse(jf2)["temporal"]["tracks"], t["tracks"]);

  // Another motion window into the same directory is refused.
  eval::PricelistOptions other = o;
  other.temporal.frames = 5;
  std::ostringstream out3, err3;
  EXPECT_EQ(eval::run_pricelist(other, out3, err3), 1);
  EXPECT_NE(err3.str().find("describes another run"), std::string::npos) << err3.str();
}

TEST(PricelistTemporal, BadTemporalOptionsAreErrorsNamingTheOption) {
  engine_test::TempDir dir;
  const auto expect_error = [&](const eval::PricelistOptions& o, const std::string& what) {
    std::ostringstream out, err;
    EXPECT_EQ(eval::run_pricelist(o, out, err), 2) << what;
    EXPECT_NE(err.str().find(what), std::string::npos) << err.str();
    EXPECT_FALSE(fs::exists(dir.path / "pl" / "run.json"));  // refused before anything is written
  };
  eval::PricelistOptions o = tiny(dir.path / "pl");
  const fs::path bad = dir.path / "bad.csv";
  std::ofstream(bad) << "time_s,qx,qy\n";
  o.temporal.motion = bad.string();
  expect_error(o, "bad.csv:1: expected the header");
  o = tiny(dir.path / "pl");
  o.temporal.frames = 1;
  expect_error(o, "--temporal-frames must be at least 2");
  o = tiny(dir.path / "pl");
  o.temporal.start_s = 3.99;  // 4 frames at 70 fps end after the 4 s motion
  expect_error(o, "past the motion's end");
  o = tiny(dir.path / "pl");
  o.temporal.fps = -70.0;
  expect_error(o, "--temporal-fps");
  o = tiny(dir.path / "pl");
  o.temporal.reference_spp = 7;
  expect_error(o, "--temporal-reference-spp");
  o = tiny(dir.path / "pl");
  o.temporal.size_px = glm::ivec2(4, 4);
  expect_error(o, "--temporal-size");
}

TEST(PricelistTemporal, AcceptanceReadsTheRatiosAgainstItsGoals) {
  //                         0-2.5 2.5-5 5-10 10-20 20-30 30-45 >45
  const std::array<double, 7> off = {0.1, 0.1, 0.1, 0.1, 0.10, 0.10, 0.10};
  const std::array<double, 7> rep = {0.1, 0.1, 0.1, 0.1, 0.019, 0.01, 0.0195};  // 5.3x, 10x, 5.1x
  const std::array<double, 7> psnr_off = {30, 30, 30, 30, 30, 30, 30};
  const std::array<double, 7> psnr_rep = {30, 30.5, 29, 29, 29, 29, 29};  // central: +0, +0.5
  Json a = eval::temporal_acceptance(synthetic(off, rep, psnr_off, psnr_rep), "s");
  ASSERT_TRUE(a.is_object());
  EXPECT_NEAR(a["flicker_ratio_off_over_image"][5].get<double>(), 10.0, 1e-12);
  EXPECT_NEAR(a["psnr_image_minus_off_db"][1].get<double>(), 0.5, 1e-12);
  EXPECT_TRUE(a["peripheral_flicker_5x_lower"].get<bool>());
  EXPECT_TRUE(a["central_error_no_worse"].get<bool>());
  // 4.9x in one peripheral ring misses the goal; so does 0.1 dB worse in the fovea.
  std::array<double, 7> rep2 = rep;
  rep2[6] = 0.1 / 4.9;
  std::array<double, 7> psnr_rep2 = psnr_rep;
  psnr_rep2[0] = 29.9;
  a = eval::temporal_acceptance(synthetic(off, rep2, psnr_off, psnr_rep2), "s");
  EXPECT_FALSE(a["peripheral_flicker_5x_lower"].get<bool>());
  EXPECT_FALSE(a["central_error_no_worse"].get<bool>());
  EXPECT_NE(eval::temporal_headline(synthetic(off, rep2, psnr_off, psnr_rep2), a).find("4.9x"), std::string::npos);
  // Without per-frame values (a resumed older run) there is no settled comparison, and no picture.
  EXPECT_FALSE(a.contains("settled_periphery"));
  {
    engine_test::TempDir plots;
    EXPECT_EQ(eval::write_temporal_plots(plots.path, synthetic(off, rep2, psnr_off, psnr_rep2), a), "");
    EXPECT_FALSE(fs::exists(plots.path / eval::kTemporalPlotFixed));
    EXPECT_FALSE(fs::exists(plots.path / eval::kTemporalPlotTracked));
  }
  // With them, the settled periphery's ratios read the bands' settled values.
  Json with_bands = synthetic(off, rep, psnr_off, psnr_rep);
  const auto periphery = [](double flicker, double tracked) {
    return Json::array({{{"band", "centre"}, {"settled", {{"flicker", 1.0}, {"flicker_tracked", 1.0}}}},
                        {{"band", "periphery"}, {"settled", {{"flicker", flicker}, {"flicker_tracked", tracked}}}}});
  };
  with_bands["tracks"][0]["bands"] = periphery(0.06, 0.05);
  with_bands["tracks"][2]["bands"] = periphery(0.03, 0.01);
  with_bands["reference"] = {{"settle_frames", 10}, {"settled_frames", 13}, {"rings", Json::array()},
                             {"history_on_reference_bands", periphery(0.02, 0.004)},
                             {"sample_history_bands", periphery(0.015, 0.01)}};
  a = eval::temporal_acceptance(with_bands, "s");
  ASSERT_TRUE(a.contains("settled_periphery")) << a.dump();
  const Json& settled = a["settled_periphery"];
  EXPECT_EQ(settled["frames"], 13);
  EXPECT_EQ(settled["settle_frames"], 10);
  EXPECT_NEAR(settled["flicker_ratio_off_over_image"].get<double>(), 2.0, 1e-12);
  EXPECT_NEAR(settled["flicker_tracked_ratio_off_over_image"].get<double>(), 5.0, 1e-12);
  EXPECT_NEAR(settled["flicker_ratio_off_over_history_on_reference"].get<double>(), 3.0, 1e-12);
  EXPECT_NEAR(settled["flicker_tracked_ratio_off_over_history_on_reference"].get<double>(), 12.5, 1e-12);
  EXPECT_NEAR(settled["flicker_ratio_off_over_sample_history"].get<double>(), 4.0, 1e-12);
  EXPECT_NEAR(settled["flicker_tracked_ratio_off_over_sample_history"].get<double>(), 5.0, 1e-12);
  EXPECT_TRUE(settled["flicker_ratio_off_over_stable_blur"].is_null());  // that control has no bands here
  // Per-frame values draw both pictures; into a directory that cannot be written, the error names the file.
  for (const std::size_t i : {std::size_t(0), std::size_t(2)}) {
    with_bands["tracks"][i]["bands"][1]["flicker_by_frame"] = Json::array({nullptr, 0.05, 0.04});
    with_bands["tracks"][i]["bands"][1]["flicker_tracked_by_frame"] = Json::array({nullptr, 0.03, 0.02});
  }
  {
    engine_test::TempDir plots;
    EXPECT_EQ(eval::write_temporal_plots(plots.path, with_bands, a), "");
    EXPECT_GT(fs::file_size(plots.path / eval::kTemporalPlotFixed), 1000u);
    EXPECT_GT(fs::file_size(plots.path / eval::kTemporalPlotTracked), 1000u);
    const std::string e = eval::write_temporal_plots(plots.path / "missing" / "dir", with_bands, a);
    EXPECT_NE(e.find(eval::kTemporalPlotFixed), std::string::npos) << e;
  }
  // The setting's render-cache track gets the same goal, read from its own rings: 6x along the motion in every
  // peripheral ring but 4x at fixed pixels in one; 1 dB better at 0-2.5 deg but 0.2 dB worse at 2.5-5 deg.
  Json with_cache = synthetic(off, rep, psnr_off, psnr_rep);
  EXPECT_FALSE(eval::temporal_acceptance(with_cache, "s").contains("render_cache"));
  EXPECT_EQ(eval::temporal_render_cache_line(eval::temporal_acceptance(with_cache, "s")), "");
  for (Json& ring : with_cache["tracks"][0]["rings"]) ring["flicker_tracked"] = ring["flicker"];
  Json cache_rings = Json::array();
  for (std::size_t r = 0; r < 7; ++r)
    cache_rings.push_back({{"flicker", r == 5 ? 0.025 : 0.015},
                           {"flicker_tracked", 0.1 / 6.0},
                           {"psnr", r == 0 ? 31.0 : r == 1 ? 29.8 : 35.0}});
  with_cache["tracks"].push_back({{"id", "s_temporal-rays"}, {"temporal", "rays"}, {"rings", cache_rings}});
  a = eval::temporal_acceptance(with_cache, "s");
  ASSERT_TRUE(a.contains("render_cache")) << a.dump();
  const Json& cache_goal = a["render_cache"];
  EXPECT_NEAR(cache_goal["flicker_ratio"][5].get<double>(), 4.0, 1e-12);
  EXPECT_NEAR(cache_goal["flicker_tracked_ratio"][6].get<double>(), 6.0, 1e-12);
  EXPECT_FALSE(cache_goal["peripheral_flicker_5x_lower"].get<bool>());
  EXPECT_TRUE(cache_goal["peripheral_tracked_flicker_5x_lower"].get<bool>());
  EXPECT_NEAR(cache_goal["psnr_minus_off_db"][0].get<double>(), 1.0, 1e-12);
  EXPECT_NEAR(cache_goal["psnr_minus_off_db"][1].get<double>(), -0.2, 1e-9);
  EXPECT_FALSE(cache_goal["central_error_no_worse"].get<bool>());
  EXPECT_TRUE(a["peripheral_flicker_5x_lower"].get<bool>());  // the image history's goal is its own
  const std::string cache_line = eval::temporal_render_cache_line(a);
  EXPECT_NE(cache_line.find("6.7x / 4.0x / 6.7x"), std::string::npos) << cache_line;
  EXPECT_NE(cache_line.find("6.0x / 6.0x / 6.0x"), std::string::npos) << cache_line;
  EXPECT_NE(cache_line.find("goal 5x: not met / met"), std::string::npos) << cache_line;
  EXPECT_NE(cache_line.find("+1.0 / -0.2 dB"), std::string::npos) << cache_line;
  // A setting without its three tracks has no acceptance.
  EXPECT_TRUE(eval::temporal_acceptance(synthetic(off, rep, psnr_off, psnr_rep), "other").is_null());
}
