// `fovea-eval pricelist`: the grid with its full renders with history, the Pareto front,
// the full render at equal time, a tiny sweep whose CSV agrees with its JSON
// and whose written images reproduce its per-ring PSNR, resume, bad grids.
#include "gltf_fixtures.hpp"

#include <eval/cmd_density.hpp>
#include <eval/cmd_pricelist.hpp>
#include <eval/pfm.hpp>
#include <eval/pricelist_report.hpp>
#include <eval/reference.hpp>

#include <engine/gltf_loader.hpp>
#include <engine/render.hpp>
#include <engine/tracer.hpp>
#include <foveation/executor.hpp>
#include <metrics/image_metrics.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>

namespace fs = std::filesystem;
using namespace foveart;

namespace {

std::size_t count_lines(const fs::path& file) {
  std::ifstream in(file);
  std::size_t n = 0;
  std::string line;
  while (std::getline(in, line)) ++n;
  return n;
}

// Ring 0 PSNR and time fraction as given; kind from the id.
nlohmann::ordered_json result(const std::string& id, double time_fraction, double psnr0) {
  nlohmann::ordered_json rings = nlohmann::ordered_json::array();
  rings.push_back({{"psnr", std::isnan(psnr0) ? nlohmann::ordered_json() : nlohmann::ordered_json(psnr0)}});
  return {{"id", id}, {"kind", id.rfind("full", 0) == 0 ? "full" : "foveated"}, {"time_fraction", time_fraction},
          {"rings", rings}};
}

}  // namespace

TEST(Pricelist, ParetoFrontKeepsTheUndominated) {
  //                 cost:  1    2    3    4    5   NaN
  const std::vector<double> cost = {1, 2, 3, 4, 5, NAN};
  const std::vector<double> acc = {10, 9, 20, 20, 30, 99};
  EXPECT_EQ(eval::pareto_front(cost, acc), (std::vector<std::size_t>{0, 2, 4}));
}

TEST(Pricelist, ExpandGridAddsTheFullRenderWithHistoryAtEveryHistoryRayCount) {
  eval::PriceGrid g;
  g.full_rays_per_point = {1, 2};
  g.interpolation = {"nearest:1"};
  g.density_scale = {1.0};
  g.rays_per_point = {1};
  g.pattern = {"thesis"};
  g.history_rays_per_point = {1, 4};
  g.content_contrast.clear();  // the content-aware family has its own test
  g.content_rays.clear();
  std::vector<eval::PriceSetting> settings;
  std::string error;
  ASSERT_TRUE(eval::expand_grid(g, &settings, &error)) << error;
  std::vector<std::string> ids;
  for (const eval::PriceSetting& s : settings) ids.push_back(s.id());
  EXPECT_EQ(ids, (std::vector<std::string>{"full_spp1", "full_spp2", "full_spp1_image", "full_spp4_image",
                                           "nearest_k1_s1_thesis_r1", "nearest_k1_s1_thesis_r1_image",
                                           "nearest_k1_s1_thesis_r4_image"}));
  EXPECT_TRUE(settings[3].full && settings[3].history && settings[3].rays_per_point == 4);
  EXPECT_EQ(settings[3].table_id(), "full");
  g.history_rays_per_point.clear();  // --history-rays-per-point none: no rows with history, full or foveated
  ASSERT_TRUE(eval::expand_grid(g, &settings, &error)) << error;
  EXPECT_TRUE(std::none_of(settings.begin(), settings.end(), [](const auto& s) { return s.history; }));
  g.history_rays_per_point = {0};
  EXPECT_FALSE(eval::expand_grid(g, &settings, &error));
  EXPECT_NE(error.find("history rays per point 0"), std::string::npos) << error;
  // --quick lists the full render with history at its history ray count.
  ASSERT_TRUE(eval::expand_grid(eval::quick_grid(), &settings, &error)) << error;
  EXPECT_EQ(std::count_if(settings.begin(), settings.end(), [](const auto& s) { return s.id() == "full_spp1_image"; }),
            1);
}

TEST(Pricelist, ContentContrastRowsTraceFewerRaysThanTheirEccentricityOnlyTwins) {
  eval::PriceGrid g;
  g.full_rays_per_point = {1};
  g.interpolation = {"msm:5"};
  g.density_scale = {4.0};
  g.rays_per_point = {1};
  g.pattern = {"pixel-grid"};
  g.history_rays_per_point.clear();
  g.content_contrast = {0.0, 1.5};
  std::vector<eval::PriceSetting> settings;
  std::string error;
  EXPECT_FALSE(eval::expand_grid(g, &settings, &error));
  EXPECT_NE(error.find("content contrast 1.5"), std::string::npos) << error;

  engine_test::TempDir dir;
  eval::PricelistOptions o;
  o.size_px = glm::ivec2(320, 360);  // with scale 4 the pixel-exact fovea ends inside the view
  o.out_dir = (dir.path / "pl").string();
  o.reference_spp = "8";
  o.frames = 2;  // the second frame thins by the first's contrast
  o.threads = 2;
  o.grid = g;
  o.grid.content_contrast = {0.0, 1.0};
  o.temporal.motion = "none";
  std::ostringstream out, err;
  ASSERT_EQ(eval::run_pricelist(o, out, err), 0) << err.str();
  std::ifstream jf(fs::path(o.out_dir) / "pricelist.json");
  const auto doc = nlohmann::json::parse(jf);
  std::map<std::string, nlohmann::json> by_id;
  for (const auto& s : doc["settings"]) by_id[s["id"].get<std::string>()] = s;
  ASSERT_TRUE(by_id.count("msm_k5_s4_pixel-grid_r1")) << doc["settings"].dump();
  ASSERT_TRUE(by_id.count("msm_k5_s4_pixel-grid_r1_c1"));
  EXPECT_DOUBLE_EQ(by_id["full_spp1"]["ray_fraction"].get<double>(), 1.0);
  const double eccentricity_only = by_id["msm_k5_s4_pixel-grid_r1"]["ray_fraction"].get<double>();
  const double content = by_id["msm_k5_s4_pixel-grid_r1_c1"]["ray_fraction"].get<double>();
  EXPECT_LT(eccentricity_only, 1.0);
  EXPECT_LT(content, eccentricity_only) << "the content rows trace fewer rays";
  EXPECT_GT(content, 0.0);
  EXPECT_EQ(by_id["msm_k5_s4_pixel-grid_r1_c1"]["content_contrast"], 1.0);

  // The perceptual columns against the reference, beside full_spp1's: where content-aware density
  // thins (the periphery, fewer rays than the eccentricity-only twin) its difference is no less
  // visible; the ring with the most pixels outside the fovea, and the whole image.
  const auto& c0 = by_id["msm_k5_s4_pixel-grid_r1"];
  const auto& c1 = by_id["msm_k5_s4_pixel-grid_r1_c1"];
  EXPECT_EQ(c1["p_detect_against"], "reference");
  EXPECT_EQ(c1["p_detect_baseline"], "full_spp1");
  EXPECT_EQ(c1["p_detect_full_mean"], c0["p_detect_full_mean"]) << "one baseline for both";
  std::size_t periphery = 1;
  for (std::size_t r = 1; r < c0["rings"].size(); ++r)
    if (c0["rings"][r]["pixels"].get<double>() > c0["rings"][periphery]["pixels"].get<double>()) periphery = r;
  for (std::size_t r = 0; r < c0["rings"].size(); ++r)
    std::cout << "ring " << r << " pixels " << c0["rings"][r]["pixels"] << " p_detect_mean/share " << c0["rings"][r]["p_detect_mean"] << " "
              << c0["rings"][r]["p_detect_share"] << " | content " << c1["rings"][r]["p_detect_mean"] << " "
              << c1["rings"][r]["p_detect_share"] << " psnr " << c0["rings"][r]["psnr"] << " " << c1["rings"][r]["psnr"] << "\n";
  std::cout << "p_detect_mean ring " << periphery << ": eccentricity only " << c0["rings"][periphery]["p_detect_mean"]
            << ", content " << c1["rings"][periphery]["p_detect_mean"] << "; image " << c0["p_detect_mean"] << ", "
            << c1["p_detect_mean"] << "\n";
  EXPECT_GE(c1["rings"][periphery]["p_detect_mean"].get<double>(), c0["rings"][periphery]["p_detect_mean"].get<double>());
  EXPECT_GE(c1["p_detect_mean"].get<double>(), c0["p_detect_mean"].get<double>());
  EXPECT_GT(c0["p_detect_mean"].get<double>(), 0.0) << "interpolation differs from the full render somewhere";
}

TEST(Pricelist, ExpandGridAddsTheContentFamilyBesideTheEccentricityOnlyRows) {
  eval::PriceGrid g;
  g.full_rays_per_point = {1};
  g.interpolation = {"nearest:1"};
  g.density_scale = {2.0};
  g.rays_per_point = {1, 4};
  g.pattern = {"thesis"};
  g.history_rays_per_point = {1};
  g.content_contrast = {0.0, 0.5};  // 0: the eccentricity-only rows, always there
  g.content_rays = {0.25};
  std::vector<eval::PriceSetting> settings;
  std::string error;
  ASSERT_TRUE(eval::expand_grid(g, &settings, &error)) << error;
  std::vector<std::string> ids;
  for (const eval::PriceSetting& s : settings) ids.push_back(s.id());
  EXPECT_EQ(ids, (std::vector<std::string>{"full_spp1", "full_spp1_image", "nearest_k1_s2_thesis_r1",
                                           "nearest_k1_s2_thesis_r4", "nearest_k1_s2_thesis_r1_image",
                                           "nearest_k1_s2_thesis_r1_c0.5", "nearest_k1_s2_thesis_r4_c0.5",
                                           "nearest_k1_s2_thesis_r4_cr0.25"}))
      << "content rows without history; rays per point by content only above 1 ray per point";
  EXPECT_EQ(settings.back().content_rays, 0.25);
  EXPECT_EQ(settings.back().content_contrast, 0.0);
  EXPECT_EQ(settings.back().table_id(), settings[2].table_id()) << "one set of tables for the family";
  g.content_rays = {0.0};
  EXPECT_FALSE(eval::expand_grid(g, &settings, &error));
  EXPECT_NE(error.find("content rays 0"), std::string::npos) << error;
  // The full grid's defaults and --quick list the family.
  for (const eval::PriceGrid& grid : {eval::PriceGrid{}, eval::quick_grid()}) {
    ASSERT_TRUE(eval::expand_grid(grid, &settings, &error)) << error;
    EXPECT_TRUE(std::any_of(settings.begin(), settings.end(), [](const auto& s) { return s.content_contrast > 0.0; }));
    EXPECT_TRUE(std::any_of(settings.begin(), settings.end(), [](const auto& s) { return s.content_rays > 0.0; }));
  }
  EXPECT_EQ(eval::PriceGrid{}.content_contrast, (std::vector<double>{0.25, 0.5, 1.0}));
}

namespace {

// A made-up row for the detection summary: its ray fraction and per ring its largest P and its
// full render's (NaN: none); kind from the id, content contrast from a "_c" in it.
nlohmann::ordered_json detection_row(const std::string& id, double ray_fraction, const std::vector<double>& p_max,
                                     const std::vector<double>& full_p_max) {
  nlohmann::ordered_json rings = nlohmann::ordered_json::array();
  const auto or_null = [](double v) { return std::isnan(v) ? nlohmann::ordered_json() : nlohmann::ordered_json(v); };
  for (std::size_t r = 0; r < metrics::kRingCount; ++r)
    rings.push_back({{"psnr", 30.0}, {"p_detect_max", or_null(p_max[r])}, {"p_detect_full_max", or_null(full_p_max[r])}});
  const bool full = id.rfind("full", 0) == 0;
  const auto c = id.find("_c");
  return {{"id", id}, {"kind", full ? "full" : "foveated"}, {"temporal", id.ends_with("_image") ? "image" : "off"},
          {"content_contrast", c == std::string::npos ? 0.0 : std::stod(id.substr(c + 2))},
          {"ray_fraction", ray_fraction}, {"time_fraction", ray_fraction}, {"psnr", 30.0},
          {"p_detect_max", or_null(*std::max_element(p_max.begin(), p_max.end()))},
          {"p_detect_full_max", or_null(*std::max_element(full_p_max.begin(), full_p_max.end()))}, {"rings", rings}};
}

}  // namespace

TEST(Density, SameDetectionAllowsOnePercentagePointPerRingAndNoNewRing) {
  const double n = NAN;
  const std::vector<double> eccentricity = {0.42, 0.72, 0.54, 0.98, 0.63, n, n};
  EXPECT_TRUE(eval::detected_no_more(eccentricity, eccentricity));
  EXPECT_TRUE(eval::detected_no_more({0.40, 0.72, 0.55, 0.98, 0.10, n, n}, eccentricity)) << "0.01 higher, or lower";
  EXPECT_FALSE(eval::detected_no_more({0.42, 0.72, 0.54, 1.00, 0.63, n, n}, eccentricity)) << "0.02 higher in ring 3";
  EXPECT_FALSE(eval::detected_no_more({0.42, 0.72, 0.54, 0.98, 0.63, 0.1, n}, eccentricity)) << "a ring the baseline lacks";
  EXPECT_FALSE(eval::detected_no_more({0.42, n, 0.54, 0.98, 0.63, n, n}, eccentricity)) << "a ring without its P";
}

TEST(Pricelist, SmallestUnseenRayFractionSkipsRowsSeenWhereTheFullRenderIsNot) {
  const double n = NAN;
  //                                       rings: 0     1     2     3     4     5     6
  const std::vector<double> full = {0.1, 0.9, 0.2, 0.2, 0.2, 0.2, n};  // ring 1: the full render is seen
  EXPECT_TRUE(eval::unseen_in_every_ring({0.4, 0.99, 0.3, 0.1, 0.1, 0.1, n}, full)) << "ring 1 is not measurable";
  EXPECT_FALSE(eval::unseen_in_every_ring({0.4, 0.1, 0.5, 0.1, 0.1, 0.1, n}, full)) << "P = 0.5 in ring 2 is seen";
  EXPECT_FALSE(eval::unseen_in_every_ring({0.4, 0.1, n, 0.1, 0.1, 0.1, n}, full)) << "no P where the full render has one";
  EXPECT_EQ(eval::smallest_unseen({{0.3, true}, {0.1, false}, {0.2, true}, {0.2, true}}), std::optional<std::size_t>(2))
      << "the fewest rays among the unseen, the first on a tie";
  EXPECT_EQ(eval::smallest_unseen({{0.1, false}}), std::nullopt);

  std::vector<nlohmann::ordered_json> rows = {
      detection_row("full_spp1", 1.0, full, full),
      detection_row("nearest_k1_s1_thesis_r1", 0.30, {0.4, 0.99, 0.3, 0.1, 0.1, 0.1, n}, full),
      detection_row("nearest_k1_s2_thesis_r1", 0.12, {0.4, 0.1, 0.3, 0.1, 0.1, 0.2, n}, full),
      detection_row("nearest_k1_s3_thesis_r1", 0.05, {0.4, 0.1, 0.7, 0.6, 0.1, 0.1, n}, full),  // seen: too few
      detection_row("nearest_k1_s1_thesis_r1_image", 0.01, {0.1, 0.1, 0.1, 0.1, 0.1, 0.1, n}, full),  // history
      detection_row("nearest_k1_s1_thesis_r1_c0.5", 0.08, {0.2, 0.2, 0.2, 0.2, 0.2, 0.2, n}, full),
      detection_row("nearest_k1_s1_thesis_r1_c1", 0.04, {0.2, 0.2, 0.2, 0.2, 0.2, 0.55, n}, full)};
  rows.push_back(detection_row("nearest_k1_s2_thesis_r1_c1", 0.02, full, full));
  rows.back().erase("p_detect_max");  // no perceptual columns: in no family
  // Its full render seen in every ring: no ring to judge, in its family but never its smallest unseen.
  rows.push_back(detection_row("nearest_k1_s3_thesis_r1_c0.5", 0.01, {0.9, 0.9, 0.9, 0.9, 0.9, 0.9, 0.9},
                               {0.9, 0.9, 0.9, 0.9, 0.9, 0.9, 0.9}));
  EXPECT_EQ(eval::measurable_ring_count(full), 5u);
  EXPECT_EQ(eval::measurable_ring_count(std::vector<double>(7, 0.9)), 0u);
  const auto d = eval::detection_json(rows);
  EXPECT_EQ(rows[3]["p_unseen"], false);
  EXPECT_EQ(rows[1]["p_unseen"], true);
  EXPECT_TRUE(rows[7]["p_unseen"].is_null());
  EXPECT_TRUE(rows[8]["p_unseen"].is_null()) << "nothing to judge it by";
  std::map<std::string, nlohmann::ordered_json> by_family;
  std::vector<std::string> order;
  for (const auto& f : d["families"]) {
    order.push_back(f["family"].get<std::string>());
    by_family[order.back()] = f;
  }
  EXPECT_EQ(order, (std::vector<std::string>{"eccentricity only", "content-aware", "content-aware, contrast 0.5",
                                             "content-aware, contrast 1"}));
  const auto& eccentricity = by_family["eccentricity only"];
  EXPECT_EQ(eccentricity["rows"], 3) << "full renders and rows with history are in no family";
  EXPECT_EQ(eccentricity["unseen_rows"], 2);
  EXPECT_EQ(eccentricity["smallest_unseen"]["id"], "nearest_k1_s2_thesis_r1");
  EXPECT_EQ(eccentricity["fewest_rays"]["id"], "nearest_k1_s3_thesis_r1");
  EXPECT_EQ(eccentricity["fewest_rays"]["rings_seen"], (nlohmann::ordered_json{"5-10", "10-20"}));
  EXPECT_EQ(by_family["content-aware"]["smallest_unseen"]["id"], "nearest_k1_s1_thesis_r1_c0.5");
  EXPECT_EQ(by_family["content-aware"]["rows"], 3);
  EXPECT_EQ(by_family["content-aware"]["judged_rows"], 2);
  EXPECT_EQ(by_family["content-aware"]["fewest_rays"]["id"], "nearest_k1_s1_thesis_r1_c1");
  EXPECT_TRUE(by_family["content-aware, contrast 1"]["smallest_unseen"].is_null());
  // The goal: 4 rows at or below 10 %, 3 of them judged, one of those unseen (the content row at 8 %).
  EXPECT_EQ(d["goal"]["rows_at_or_below"], 4);
  EXPECT_EQ(d["goal"]["judged_at_or_below"], 3);
  EXPECT_EQ(d["goal"]["unseen_at_or_below"], 1);
  EXPECT_TRUE(d["goal"]["met"].get<bool>());
  EXPECT_EQ(d["goal"]["rows_seen_per_ring"], (nlohmann::ordered_json{0, 0, 1, 1, 0, 1, 0}));
  rows[5] = detection_row("nearest_k1_s1_thesis_r1_c0.5", 0.11, {0.2, 0.2, 0.2, 0.2, 0.2, 0.2, n}, full);
  EXPECT_FALSE(eval::detection_json(rows)["goal"]["met"].get<bool>()) << "its only unseen row now costs 11 %";
}

TEST(Pricelist, PerceptualColumnsPutEachRowBesideTheFullRenderAtItsRaysPerPixel) {
  engine_test::TempDir dir;
  eval::PricelistOptions o;
  o.size_px = glm::ivec2(48, 54);
  o.out_dir = (dir.path / "pl").string();
  o.reference_spp = "8";
  o.frames = 1;
  o.threads = 2;
  o.grid.full_rays_per_point = {1};  // full_spp2 is added: the foveated row traces 2 rays per point
  o.grid.interpolation = {"nearest:1"};
  o.grid.density_scale = {1.0};
  o.grid.rays_per_point = {2};
  o.grid.pattern = {"thesis"};
  o.grid.history_rays_per_point.clear();
  o.grid.content_contrast.clear();
  o.grid.content_rays.clear();
  o.temporal.motion = "none";
  std::ostringstream out, err;
  ASSERT_EQ(eval::run_pricelist(o, out, err), 0) << err.str();
  std::ifstream jf(fs::path(o.out_dir) / "pricelist.json");
  const auto doc = nlohmann::json::parse(jf);
  std::map<std::string, nlohmann::json> by_id;
  for (const auto& s : doc["settings"]) by_id[s["id"].get<std::string>()] = s;
  ASSERT_TRUE(by_id.count("full_spp2")) << doc["settings"].dump();
  const auto& fov = by_id["nearest_k1_s1_thesis_r2"];
  EXPECT_EQ(fov["p_detect_against"], "reference");
  EXPECT_EQ(fov["p_detect_baseline"], "full_spp2");
  EXPECT_EQ(by_id["full_spp2"]["p_detect_baseline"], "full_spp2");
  EXPECT_EQ(fov["p_detect_full_max"], by_id["full_spp2"]["p_detect_max"]) << "the baseline is full_spp2's own";
  EXPECT_EQ(by_id["full_spp1"]["p_detect_full_max"], by_id["full_spp1"]["p_detect_max"]);
  for (const auto& [id, s] : by_id) {
    for (const char* k : {"p_detect_mean", "p_detect_share", "p_detect_max", "p_detect_full_mean"}) {
      ASSERT_TRUE(s[k].is_number()) << id << " " << k;
      EXPECT_GE(s[k].get<double>(), 0.0) << id << " " << k;
      EXPECT_LE(s[k].get<double>(), 1.0) << id << " " << k;
    }
    for (const auto& ring : s["rings"]) {
      if (ring["pixels"].get<double>() == 0.0) continue;
      ASSERT_TRUE(ring["p_detect_mean"].is_number()) << id;
      // P < 0.5 outside the share: the mean is at most 0.5 + 0.5 share.
      EXPECT_LE(ring["p_detect_mean"].get<double>(), 0.5 + 0.5 * ring["p_detect_share"].get<double>() + 1e-12) << id;
      EXPECT_LE(ring["p_detect_mean"].get<double>(), ring["p_detect_max"].get<double>()) << id;
      if (s["kind"] == "full") {
        EXPECT_EQ(ring["p_detect_mean"], ring["p_detect_full_mean"]) << id << ": its own baseline";
      }
    }
  }
  EXPECT_GT(fov["p_detect_max"].get<double>(), 0.0) << "the frame is not the converged reference";
  EXPECT_GE(fov["p_detect_max"].get<double>(), fov["p_detect_mean"].get<double>());
}

TEST(Pricelist, EqualTimePicksTheMostAccurateFullRenderNoSlower) {
  const std::vector<nlohmann::ordered_json> all = {
      result("full_spp1", 1.0, 30.0),      result("full_spp2", 2.0, 33.0),  result("full_spp4", 4.0, 36.0),
      result("full_spp1_image", 1.1, 36.0),  result("full_spp8", 0.2, NAN),   // no PSNR in the ring: never picked
      result("fov_cheap", 0.5, 31.0),      result("fov_a", 1.05, 32.0),     result("fov_b", 1.5, 34.0),
      result("fov_c", 5.0, 40.0),          result("fov_fast_good", 0.9, 50.0)};
  const auto pick = [&](std::size_t of) {
    const std::optional<std::size_t> f = eval::equal_time_full(all, of, 0);
    return f ? all[*f]["id"].get<std::string>() : std::string("none that cheap");
  };
  EXPECT_EQ(pick(5), "none that cheap");  // every full render with a PSNR takes longer
  EXPECT_EQ(pick(6), "full_spp1");
  EXPECT_EQ(pick(7), "full_spp1_image");   // the history beats more rays per pixel at this time
  EXPECT_EQ(pick(8), "full_spp1_image");   // a tie with full_spp4 at 36 dB: the cheaper
  EXPECT_EQ(pick(9), "none that cheap");  // a foveated setting is never the baseline
  EXPECT_EQ(pick(0), "full_spp1");        // a full render's own: itself at most
}

TEST(Pricelist, TinySweepWritesConsistentJsonCsvAndImagesAndResumes) {
  engine_test::TempDir dir;
  eval::PricelistOptions o;
  o.size_px = glm::ivec2(48, 54);
  o.out_dir = (dir.path / "pl").string();
  o.reference_spp = "32";
  o.frames = 1;
  o.history_frames = 3;
  o.threads = 2;
  o.images = true;
  o.grid.full_rays_per_point = {1, 4};
  o.grid.interpolation = {"nearest:1"};
  o.grid.density_scale = {1.0};
  o.grid.rays_per_point = {1};
  o.grid.pattern = {"thesis", "pixel-grid"};
  o.grid.history_rays_per_point = {1};
  o.grid.content_contrast = {0.5};
  o.grid.content_rays = {0.5};  // none at 1 ray per point
  o.temporal.motion = "none";  // the temporal columns have their own test (pricelist_temporal_test.cpp)
  std::ostringstream out, err;
  ASSERT_EQ(eval::run_pricelist(o, out, err), 0) << err.str();
  EXPECT_NE(out.str().find("At the thesis's default"), std::string::npos) << out.str();
  EXPECT_FALSE(fs::exists(fs::path(o.out_dir) / "temporal.csv"));
  const fs::path pl = o.out_dir;
  std::ifstream jf(pl / "pricelist.json");
  const auto doc = nlohmann::json::parse(jf);
  const auto& settings = doc["settings"];
  ASSERT_EQ(settings.size(), 9u);  // full 1, 4, 1 + history; per pattern nn r1, nn r1 + history, nn r1 c0.5
  EXPECT_EQ(count_lines(pl / "pricelist.csv"), settings.size() + 1);
  for (const char* f : {"pricelist.png", "pareto_ring0.png", "report.md", "heatmap.png", "images/reference.pfm"})
    EXPECT_TRUE(fs::exists(pl / f)) << f;
  EXPECT_EQ(doc["reference"]["spp"], 32);
  EXPECT_TRUE(doc["sanity"].contains("full_error_falls_with_spp"));

  // CSV and JSON agree: the ring-0 PSNR column of each row.
  {
    std::ifstream cf(pl / "pricelist.csv");
    std::string header, line;
    std::getline(cf, header);
    std::vector<std::string> cols;
    std::stringstream hs(header);
    for (std::string c; std::getline(hs, c, ',');) cols.push_back(c);
    const auto col = std::find(cols.begin(), cols.end(), "psnr_0-2.5") - cols.begin();
    ASSERT_LT(std::size_t(col), cols.size());
    const auto eq_col = std::find(cols.begin(), cols.end(), "equal_time_full_0-2.5") - cols.begin();
    ASSERT_LT(std::size_t(eq_col), cols.size());
    const auto p_col = std::find(cols.begin(), cols.end(), "p_detect_mean_0-2.5") - cols.begin();
    ASSERT_LT(std::size_t(p_col), cols.size());
    EXPECT_EQ(cols.back(), "p_detect_full_max_>45") << "the perceptual columns are appended at the end";
    const auto unseen_col = std::find(cols.begin(), cols.end(), "p_unseen") - cols.begin();
    ASSERT_LT(std::size_t(unseen_col), cols.size());
    for (const auto& s : settings) {
      ASSERT_TRUE(std::getline(cf, line));
      std::vector<std::string> cells;
      std::stringstream ls(line);
      for (std::string c; std::getline(ls, c, ',');) cells.push_back(c);
      EXPECT_EQ(cells[0], s["id"].get<std::string>());
      if (s["rings"][0]["psnr"].is_number()) {
        EXPECT_NEAR(std::stod(cells[std::size_t(col)]), s["rings"][0]["psnr"].get<double>(), 1e-9);
      }
      ASSERT_LT(std::size_t(eq_col), cells.size()) << line;
      ASSERT_LT(std::size_t(p_col), cells.size()) << line;
      ASSERT_TRUE(s["rings"][0]["p_detect_mean"].is_number()) << s["id"];
      EXPECT_NEAR(std::stod(cells[std::size_t(p_col)]), s["rings"][0]["p_detect_mean"].get<double>(), 1e-12);
      const std::optional<bool> unseen = eval::row_unseen(s);  // none: its full render is seen in every ring
      EXPECT_EQ(s["p_unseen"], unseen ? nlohmann::json(*unseen) : nlohmann::json()) << s["id"];
      EXPECT_EQ(cells[std::size_t(unseen_col)], !unseen ? "" : *unseen ? "1" : "0") << s["id"];
      if (s["kind"] == "foveated") {
        const auto& e = s["equal_time_full"][0];
        EXPECT_EQ(cells[std::size_t(eq_col)], e.is_null() ? "none" : e["id"].get<std::string>()) << s["id"];
      }
    }
  }

  // A person's own recomputation from the written images: PSNR per ring over
  // the display values in the PFMs and the ring index in eccentricity.pfm.
  foveation::ImageRgb ref, ecc;
  std::string error;
  ASSERT_TRUE(eval::read_pfm((pl / "images/reference.pfm").string(), &ref, &error)) << error;
  ASSERT_TRUE(eval::read_pfm((pl / "images/eccentricity.pfm").string(), &ecc, &error)) << error;
  for (const auto& s : settings) {
    foveation::ImageRgb im;
    ASSERT_TRUE(eval::read_pfm((pl / s["image"].get<std::string>()).string(), &im, &error)) << s["id"] << error;
    std::vector<double> se(metrics::kRingCount, 0.0), n(metrics::kRingCount, 0.0);
    for (std::size_t i = 0; i < im.pixel_count(); ++i) {
      const auto r = std::size_t(ecc.rgb[i * 3 + 1]);
      for (int c = 0; c < 3; ++c) se[r] += std::pow(double(im.rgb[i * 3 + c]) - double(ref.rgb[i * 3 + c]), 2.0);
      n[r] += 3;
    }
    for (std::size_t r = 0; r < metrics::kRingCount; ++r) {
      const auto& json_psnr = s["rings"][r]["psnr"];
      if (n[r] == 0 || !json_psnr.is_number()) continue;
      EXPECT_NEAR(10.0 * std::log10(n[r] / se[r]), json_psnr.get<double>(), 0.05) << s["id"] << " ring " << r;
    }
  }
  // Inside the fovea the pixel-grid pattern traces the full render's rays (same
  // pixel jitter, same seed): the same error there, to the bit.
  const auto by_id = [&](const std::string& id) {
    const auto it = std::find_if(settings.begin(), settings.end(), [&](const auto& s) { return s["id"] == id; });
    EXPECT_NE(it, settings.end()) << id;
    return *it;
  };
  const auto full1 = by_id("full_spp1"), grid1 = by_id("nearest_k1_s1_pixel-grid_r1");
  ASSERT_GT(full1["rings"][0]["pixels"].get<int>(), 0);
  EXPECT_EQ(grid1["rings"][0]["psnr"], full1["rings"][0]["psnr"]);
  const auto with_history = std::find_if(settings.begin(), settings.end(),
                                [](const auto& s) { return s["id"] == "nearest_k1_s1_thesis_r1_image"; });
  ASSERT_NE(with_history, settings.end());
  EXPECT_EQ((*with_history)["flicker_frames"], 3);
  EXPECT_GT((*with_history)["rings"][0]["flicker"].get<double>(), 0.0);  // new jitter each frame: the image moves
  // The full render with the same history: as many frames, new jitter, and inside the fovea the
  // pixel-grid fovea with history traces and blends the same rays.
  const auto full_history = by_id("full_spp1_image"), grid_history = by_id("nearest_k1_s1_pixel-grid_r1_image");
  EXPECT_EQ(full_history["kind"], "full");
  EXPECT_EQ(full_history["temporal"], "image");
  EXPECT_EQ(full_history["flicker_frames"], 3);
  EXPECT_GT(full_history["rings"][0]["flicker"].get<double>(), 0.0);
  EXPECT_EQ(grid_history["rings"][0]["psnr"], full_history["rings"][0]["psnr"]);
  EXPECT_GT(full_history["rings"][0]["psnr"].get<double>(), full1["rings"][0]["psnr"].get<double>());
  // Every foveated setting has its equal-time baseline per ring, and report.md shows it.
  for (const auto& s : settings) {
    if (s["kind"] == "foveated") {
      EXPECT_EQ(s["equal_time_full"].size(), metrics::kRingCount) << s["id"];
    }
  }
  {
    std::ifstream rf(pl / "report.md");
    std::stringstream text;
    text << rf.rdbuf();
    const std::string md = text.str();
    EXPECT_NE(md.find("| foveated on the front | time % | PSNR dB | full render no slower |"), std::string::npos);
    EXPECT_NE(md.find("With the same history (the image history over 3 frames"), std::string::npos)
        << md.substr(0, 2000);
    EXPECT_NE(md.find("At equal time "), std::string::npos) << md.substr(0, 2000);
    // The content-aware family beside the eccentricity-only rows, and every row's detection per ring.
    EXPECT_NE(md.find("## Content-aware density"), std::string::npos);
    EXPECT_NE(md.find("| eccentricity only | 2 | "), std::string::npos) << "the two rows without history";
    EXPECT_NE(md.find("| content-aware, contrast 0.5 | 2 | "), std::string::npos);
    EXPECT_NE(md.find("Goal, unseen at 10 % of the full render's rays or fewer: **"), std::string::npos);
    EXPECT_NE(md.find("## Detection per ring"), std::string::npos);
    for (const auto& s : settings) EXPECT_NE(md.find("\n| " + s["id"].get<std::string>() + " | "), std::string::npos) << s["id"];
  }
  {  // pricelist.json's summary of the same
    std::vector<std::string> families;
    for (const auto& f : doc["detection"]["families"]) families.push_back(f["family"].get<std::string>());
    EXPECT_EQ(families, (std::vector<std::string>{"eccentricity only", "content-aware", "content-aware, contrast 0.5"}));
    EXPECT_EQ(doc["detection"]["goal"]["ray_fraction"], 0.1);
    EXPECT_EQ(by_id("nearest_k1_s1_thesis_r1_c0.5")["content_contrast"], 0.5);
  }

  // Resume: nothing measured again, the same headline.
  const std::size_t lines = count_lines(pl / "results.jsonl");
  std::ostringstream out2, err2;
  ASSERT_EQ(eval::run_pricelist(o, out2, err2), 0) << err2.str();
  EXPECT_EQ(count_lines(pl / "results.jsonl"), lines);
  EXPECT_EQ(out2.str(), out.str());
  {  // its report says the settings came from the earlier run
    std::ifstream rf(pl / "report.md");
    std::stringstream text;
    text << rf.rdbuf();
    EXPECT_NE(text.str().find("(resuming: 9 settings were measured by earlier runs into the same --out)"),
              std::string::npos) << text.str().substr(0, 600);
  }
  // Results from before the full render had a history: only full_spp1_image is measured, against
  // an anchor of its own (full_spp1 is not measured again).
  {
    std::ifstream in(pl / "results.jsonl");
    std::stringstream kept;
    for (std::string line; std::getline(in, line);)
      if (nlohmann::json::parse(line)["id"] != "full_spp1_image") kept << line << "\n";
    in.close();
    std::ofstream(pl / "results.jsonl") << kept.str();
  }
  ASSERT_EQ(count_lines(pl / "results.jsonl"), lines - 1);
  std::ostringstream out5, err5;
  ASSERT_EQ(eval::run_pricelist(o, out5, err5), 0) << err5.str();
  EXPECT_EQ(count_lines(pl / "results.jsonl"), lines);
  {
    std::ifstream jf2(pl / "pricelist.json");
    const auto doc2 = nlohmann::json::parse(jf2);
    const auto it = std::find_if(doc2["settings"].begin(), doc2["settings"].end(),
                                 [](const auto& s) { return s["id"] == "full_spp1_image"; });
    ASSERT_NE(it, doc2["settings"].end());
    EXPECT_GT((*it)["anchor_full_ms"].get<double>(), 0.0) << "an anchor was rendered beside it";
    EXPECT_EQ((*it)["rings"][0]["psnr"], full_history["rings"][0]["psnr"]) << "the same frames, the same image";
  }
  // Another pixel filter, or another gaze, into the same directory is refused:
  // its settings and reference would be other images.
  o.pixel_filter = foveation::PixelFilter::bspline2;
  std::ostringstream out4, err4;
  EXPECT_EQ(eval::run_pricelist(o, out4, err4), 1);
  EXPECT_NE(err4.str().find("describes another run"), std::string::npos) << err4.str();
  o.pixel_filter = foveation::PixelFilter::box;
  o.gaze_px = glm::vec2(10, 10);
  std::ostringstream out3, err3;
  EXPECT_EQ(eval::run_pricelist(o, out3, err3), 1);
  EXPECT_NE(err3.str().find("describes another run"), std::string::npos) << err3.str();
}

TEST(Pricelist, BadGridIsAnErrorNamingTheEntry) {
  engine_test::TempDir dir;
  eval::PricelistOptions o;
  o.out_dir = dir.path.string();
  o.grid.interpolation = {"nearest:1", "foo:3"};
  std::ostringstream out, err;
  EXPECT_EQ(eval::run_pricelist(o, out, err), 2);
  EXPECT_NE(err.str().find("interpolation 'foo:3'"), std::string::npos) << err.str();
  o.grid.interpolation = {"msm:0"};
  std::ostringstream out2, err2;
  EXPECT_EQ(eval::run_pricelist(o, out2, err2), 2);
  EXPECT_NE(err2.str().find("k must be"), std::string::npos) << err2.str();
}

// `fovea-eval pricelist --md FILE`, run as a person runs it: the file is headed by the
// command line as given and the machine, holds the report's tables, and its image
// links reach into --out from where the file is.
TEST(Pricelist, MdFileNamesItsCommandAndMachine) {
  engine_test::TempDir dir;
  const fs::path fovea_eval = fs::read_symlink("/proc/self/exe").parent_path() / "fovea-eval";
  ASSERT_TRUE(fs::exists(fovea_eval)) << fovea_eval << " is missing: build the fovea-eval target";
  const fs::path md = dir.path / "results" / "pricelist.md";
  const std::string args =
      "pricelist --size 48x54 --reference-spp 32 --frames 1 --threads 2 --motion none "
      "--full-rays-per-point 1,2 --interpolation nearest:1 --density-scale 1 "
      "--rays-per-point 1 --pattern pixel-grid --history-rays-per-point none --content-contrast 0.5 "
      "--content-rays none --out " +
      (dir.path / "pl").string() + " --md " + md.string();
  const std::string cmd =
      "'" + fovea_eval.string() + "' " + args + " >/dev/null 2>'" + (dir.path / "err").string() + "'";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << std::ifstream(dir.path / "err").rdbuf();
  std::ifstream in(md);
  std::stringstream text;
  text << in.rdbuf();
  const std::string s = text.str();
  EXPECT_NE(s.find("Written by `fovea-eval " + args + "` on "), std::string::npos) << s;
  std::string cpu;
  {
    std::ifstream cpuinfo("/proc/cpuinfo");
    for (std::string line; std::getline(cpuinfo, line) && cpu.empty();) {
      if (line.rfind("model name", 0) == 0) cpu = line.substr(line.find(':') + 2);
    }
  }
  if (!cpu.empty()) {
    EXPECT_NE(s.find(cpu), std::string::npos) << "the CPU model, from /proc/cpuinfo";
  }
  EXPECT_NE(s.find(" cores; "), std::string::npos) << s;
  EXPECT_NE(s.find("| on the front | time % |"), std::string::npos) << "the ring tables";
  EXPECT_NE(s.find("| content-aware, contrast 0.5 | 1 | "), std::string::npos) << "--content-contrast's row";
  EXPECT_NE(s.find("|---|---|---|---|---|---|---|---|---|\n| "), std::string::npos) << "a table with a row";
  EXPECT_NE(s.find("](../pl/pricelist.png)"), std::string::npos) << "links into --out from the file's folder";
  EXPECT_TRUE(fs::exists(md.parent_path() / "../pl/pricelist.png"));
}
