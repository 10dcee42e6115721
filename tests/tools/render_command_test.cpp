// `fovea render` through its library entry point (run_render) and CLI11.
#include "gltf_fixtures.hpp"

#include <cmd_render.hpp>
#include <render_view/render_cli.hpp>
#include <engine/default_scene.hpp>
#include <engine/render.hpp>
#include <engine/tracer.hpp>
#include <foveation/content_density.hpp>
#include <foveation/display_model.hpp>
#include <foveation/executor.hpp>
#include <foveation/foveated_view.hpp>

#include <CLI/CLI.hpp>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <numeric>
#include <optional>
#include <sstream>
#include <vector>

using foveart::render_view::RenderOptions;
using foveart::fovea::register_render;
using foveart::fovea::run_render;

namespace {

RenderOptions small(const std::string& mode) {
  RenderOptions o;
  o.mode = mode;
  o.size_px = glm::ivec2(40, 45);
  o.threads = 2;
  o.json = true;
  return o;
}

}  // namespace

TEST(RenderCommand, FullModeJsonReportsRaysPerEffectAndTimes) {
  std::ostringstream out, err;
  ASSERT_EQ(run_render(small("full"), out, err), 0) << err.str();
  const auto j = nlohmann::json::parse(out.str());
  EXPECT_EQ(j["pixels"], 40 * 45);
  ASSERT_TRUE(j.contains("points"));
  const auto& full = j["full"];
  EXPECT_EQ(full["rays"]["primary"], 40 * 45);
  EXPECT_GT(full["rays"]["shadow"].get<uint64_t>(), 0u);
  EXPECT_GT(full["rays"]["reflection"].get<uint64_t>(), 0u);
  EXPECT_GT(full["rays"]["refraction"].get<uint64_t>(), 0u);
  EXPECT_EQ(full["reconstruct_ms"], 0.0);
  EXPECT_GE(full["total_ms"].get<double>(), full["trace_ms"].get<double>());
  EXPECT_FALSE(j.contains("foveated"));
}

// --out PREFIX: each mode's image, and a foveated render's rays map; the JSON lists them.
TEST(RenderCommand, WritesPngWithPrefix) {
  for (const auto& [mode, files] : {std::pair<std::string, std::vector<std::string>>{"full", {"_full.png"}},
                                    {"foveated", {"_foveated.png", "_rays.png"}}}) {
    engine_test::TempDir dir;
    RenderOptions o = small(mode);
    o.rays_per_point = 2;
    o.out_prefix = (dir.path / "img").string();
    std::ostringstream out, err;
    ASSERT_EQ(run_render(o, out, err), 0) << err.str();
    const nlohmann::json images = nlohmann::json::parse(out.str())["images"];
    ASSERT_EQ(images.size(), files.size()) << mode << ": " << images;
    for (std::size_t i = 0; i < files.size(); ++i) {
      EXPECT_EQ(images[i], o.out_prefix + files[i]) << mode;
      EXPECT_GT(std::filesystem::file_size(o.out_prefix + files[i]), 100u) << mode << " " << files[i];
    }
  }
}

TEST(RenderCommand, BadInputGivesMessageAndExitCode) {
  std::ostringstream out, err;
  RenderOptions o = small("full");
  o.scene = "/nonexistent/scene.gltf";
  EXPECT_EQ(run_render(o, out, err), 1);
  EXPECT_NE(err.str().find("/nonexistent/scene.gltf"), std::string::npos) << err.str();
  o = small("sideways");
  EXPECT_EQ(run_render(o, out, err), 2);
  EXPECT_NE(err.str().find("--mode"), std::string::npos);
  o = small("full");
  o.frames = 0;
  EXPECT_EQ(run_render(o, out, err), 2);
  EXPECT_NE(err.str().find("--frames"), std::string::npos);
  o = small("foveated");
  o.frames = 1;
  o.gaze_px_per_frame = {glm::vec2(4, 4), glm::vec2(8, 8)};
  err.str("");
  EXPECT_EQ(run_render(o, out, err), 2);
  EXPECT_NE(err.str().find("--gaze lists 2 gazes, more than --frames 1"), std::string::npos) << err.str();
  for (const double doubling : {-1.0, 91.0, std::nan("")}) {
    o = small("foveated");
    o.content_rays_doubling_deg = doubling;
    err.str("");
    EXPECT_EQ(run_render(o, out, err), 2) << doubling;
    EXPECT_NE(err.str().find("--content-rays-doubling must be in [0, 90]"), std::string::npos) << err.str();
  }
  o = small("foveated");
  o.content_rays_doubling_deg = 200.0;
  err.str("");
  EXPECT_EQ(run_render(o, out, err), 2);
  EXPECT_NE(err.str().find("got 200\n"), std::string::npos) << "the value as typed: " << err.str();
  o = small("foveated");
  o.content_rays = 1.5;
  err.str("");
  EXPECT_EQ(run_render(o, out, err), 2);
  EXPECT_NE(err.str().find("got 1.5\n"), std::string::npos) << "the value as typed: " << err.str();
}

TEST(RenderCommand, WithoutLeavesEffectsOutOfTheImage) {
  RenderOptions o = small("full");
  std::ostringstream out, err;
  ASSERT_EQ(run_render(o, out, err), 0) << err.str();
  const auto every = nlohmann::json::parse(out.str());
  EXPECT_EQ(every["effects"], "shadows+reflection+refraction+textures");

  o.without = "reflection,refraction";
  out.str("");
  ASSERT_EQ(run_render(o, out, err), 0) << err.str();
  const auto without = nlohmann::json::parse(out.str());
  EXPECT_EQ(without["effects"], "shadows+textures");
  EXPECT_EQ(without["full"]["rays"]["primary"], 40 * 45);
  EXPECT_GT(without["full"]["rays"]["shadow"].get<uint64_t>(), 0u);
  EXPECT_EQ(without["full"]["rays"]["reflection"], 0);
  EXPECT_EQ(without["full"]["rays"]["refraction"], 0);
  EXPECT_FALSE(without.contains("errors_against_reference"));  // accuracy is the lab's: fovea-eval accuracy

  o.without = "reflection,glitter";
  err.str("");
  EXPECT_EQ(run_render(o, out, err), 2);
  EXPECT_NE(err.str().find("--without"), std::string::npos) << err.str();
  EXPECT_NE(err.str().find("'glitter'"), std::string::npos) << err.str();
}

TEST(RenderCommand, RegistersWithCli11AndRejectsBadGaze) {
  CLI::App app;
  register_render(app);
  EXPECT_NO_THROW(app.get_subcommand("render"));
  const char* argv[] = {"fovea", "render", "--gaze", "abc", "--size", "16x16"};
  EXPECT_THROW(app.parse(6, argv), CLI::ValidationError);
  // A per-frame list is checked item by item.
  const char* list[] = {"fovea", "render", "--gaze", "8,8;abc", "--size", "16x16"};
  EXPECT_THROW(app.parse(6, list), CLI::ValidationError);
}

// --temporal is the layer's one temporal choice: the product's TemporalMode, "rays"
// brings the B-spline unless --pixel-filter says otherwise, and the lab's temporal variants and lists,
// its experiments and its reference are not the product's options.
TEST(RenderCommand, TemporalIsTheLayersChoice) {
  using foveart::foveation::PixelFilter;
  using foveart::foveation::TemporalMode;
  struct Case {
    std::vector<const char*> args;
    TemporalMode temporal;
    PixelFilter filter;
  };
  for (const Case& c : {Case{{}, TemporalMode::off, PixelFilter::box},
                        Case{{"--temporal", "image"}, TemporalMode::image, PixelFilter::box},
                        Case{{"--temporal", "rays"}, TemporalMode::rays, PixelFilter::bspline2},
                        Case{{"--temporal", "rays", "--pixel-filter", "box"}, TemporalMode::rays, PixelFilter::box}}) {
    CLI::App app;
    CLI::App* cmd = app.add_subcommand("render");
    auto opts = std::make_shared<RenderOptions>();
    foveart::render_view::add_render_options(cmd, opts);
    foveart::render_view::add_temporal_option(cmd, opts);
    std::vector<const char*> argv{"fovea", "render"};
    argv.insert(argv.end(), c.args.begin(), c.args.end());
    ASSERT_NO_THROW(app.parse(static_cast<int>(argv.size()), argv.data()));
    EXPECT_EQ(opts->temporal, c.temporal);
    EXPECT_EQ(opts->pixel_filter, c.filter);
  }
  for (std::vector<const char*> bad : {std::vector<const char*>{"fovea", "render", "--temporal", "on"},
                                       std::vector<const char*>{"fovea", "render", "--temporal", "restart"},
                                       std::vector<const char*>{"fovea", "render", "--temporal", "rays-kept"},
                                       std::vector<const char*>{"fovea", "render", "--temporal", "off,image"},
                                       std::vector<const char*>{"fovea", "render", "--taa", "reproject"},
                                       std::vector<const char*>{"fovea", "render", "--taa-mean-while-young"},
                                       std::vector<const char*>{"fovea", "render", "--reference-spp", "16"},
                                       std::vector<const char*>{"fovea", "render", "--reference", "r.pfm"}}) {
    CLI::App app;
    register_render(app);
    EXPECT_ANY_THROW(app.parse(static_cast<int>(bad.size()), bad.data())) << bad[2];
  }
}

// `fovea render` leaves rays per point by contrast to the product's default: with several rays per
// point at the thesis's density, a point casts all of them from contrast 0.5 of its tile and fewer
// below, from the second frame (the first has no contrast yet); at one ray per point, at a denser
// scale or with --content-rays 0 every point casts them all. (The lab's commands default to off.)
TEST(RenderCommand, SeveralRaysPerPointFollowTheContrastByDefault) {
  EXPECT_EQ(RenderOptions{}.content_rays, 0.0) << "the lab's rows are what they name";
  CLI::App app;
  register_render(app);  // fovea render's options start unset, and its help says what that means
  const std::string help = app.get_subcommand("render")->get_option("--content-rays")->get_description();
  EXPECT_NE(help.find("default 0.5 with several rays per point at --density-scale 1 or above"), std::string::npos)
      << help;
  struct Case {
    int rays_per_point;
    double density_scale;
    std::optional<double> content_rays;  // unset: fovea render's default
    double reported;
  };
  for (const Case& c : {Case{4, 1.0, std::nullopt, foveart::foveation::kDefaultRaysContrast},
                        Case{4, 2.0, std::nullopt, foveart::foveation::kDefaultRaysContrast},
                        Case{1, 1.0, std::nullopt, 0.0}, Case{4, 0.7, std::nullopt, 0.0}, Case{4, 1.0, 0.0, 0.0}}) {
    SCOPED_TRACE(testing::Message() << c.rays_per_point << " rays, scale " << c.density_scale << ", content rays "
                                    << (c.content_rays ? std::to_string(*c.content_rays) : "unset"));
    RenderOptions o = small("foveated");
    o.size_px = glm::ivec2(160, 180);
    o.fov.horizontal = 2.5;  // 64 px/deg: a pixel-exact fovea of about 33 px radius, Poisson points around it
    o.rays_per_point = c.rays_per_point;
    o.density_scale = c.density_scale;
    o.content_rays = c.content_rays;
    o.frames = 2;
    std::ostringstream out, err;
    ASSERT_EQ(run_render(o, out, err), 0) << err.str();
    const auto j = nlohmann::json::parse(out.str());
    const auto& fov = j["foveated"];
    EXPECT_EQ(fov["content_rays"].get<double>(), c.reported);
    const uint64_t all = j["points"].get<uint64_t>() * uint64_t(c.rays_per_point);
    if (c.reported > 0.0)
      EXPECT_LT(fov["rays"]["primary"].get<uint64_t>(), all) << "flat tiles cast fewer";
    else
      EXPECT_EQ(fov["rays"]["primary"].get<uint64_t>(), all);
  }
}

// `fovea render` leaves the doubling of that contrast with eccentricity to the product's default:
// every 30 degrees with the render cache (--temporal rays), off with the image history or none; a
// value asked for holds with any history. (The lab's commands default to off.)
TEST(RenderCommand, TheRaysDoublingFollowsTheHistoryByDefault) {
  using foveart::foveation::TemporalMode;
  EXPECT_EQ(RenderOptions{}.content_rays_doubling_deg, 0.0) << "the lab's rows are what they name";
  CLI::App app;
  register_render(app);
  const std::string help = app.get_subcommand("render")->get_option("--content-rays-doubling")->get_description();
  EXPECT_NE(help.find("default 30 with --temporal rays, else off"), std::string::npos) << help;
  struct Case {
    TemporalMode temporal;
    std::optional<double> doubling;  // unset: fovea render's default
    double expected;
  };
  for (const Case& c : {Case{TemporalMode::rays, std::nullopt, foveart::foveation::kDefaultRaysDoublingEccDeg},
                        Case{TemporalMode::image, std::nullopt, 0.0}, Case{TemporalMode::off, std::nullopt, 0.0},
                        Case{TemporalMode::rays, 0.0, 0.0}, Case{TemporalMode::image, 20.0, 20.0}}) {
    SCOPED_TRACE(testing::Message() << foveart::foveation::temporal_mode_name(c.temporal) << ", doubling "
                                    << (c.doubling ? std::to_string(*c.doubling) : "unset"));
    RenderOptions o = small("foveated");
    o.rays_per_point = 4;
    o.content_rays.reset();
    o.temporal = c.temporal;
    o.content_rays_doubling_deg = c.doubling;
    EXPECT_EQ(foveart::render_view::foveated_view_settings(o).content_density.rays_doubling_ecc_deg, float(c.expected));
    std::ostringstream out, err;
    ASSERT_EQ(run_render(o, out, err), 0) << err.str();
    EXPECT_EQ(nlohmann::json::parse(out.str())["foveated"]["content_rays_doubling_deg"].get<double>(), c.expected);
  }
}

// The render cache's kept rays after each frame: they pile up while the view holds still (its
// cost on the CPU grows with them); the image history keeps none.
TEST(RenderCommand, TheJsonCountsTheRenderCachesRaysPerFrame) {
  using foveart::foveation::TemporalMode;
  for (const TemporalMode temporal : {TemporalMode::rays, TemporalMode::image}) {
    RenderOptions o = small("foveated");
    o.temporal = temporal;
    o.frames = 3;
    std::ostringstream out, err;
    ASSERT_EQ(run_render(o, out, err), 0) << err.str();
    const nlohmann::json kept = nlohmann::json::parse(out.str())["foveated"]["frames_cached_rays"];
    ASSERT_EQ(kept.size(), 3u) << kept;
    if (temporal == TemporalMode::image) {
      EXPECT_EQ(kept, nlohmann::json::array({0, 0, 0}));
      continue;
    }
    EXPECT_GT(kept[0].get<std::uint64_t>(), 0u);
    EXPECT_GT(kept[1].get<std::uint64_t>(), kept[0].get<std::uint64_t>()) << kept;
    EXPECT_GT(kept[2].get<std::uint64_t>(), kept[1].get<std::uint64_t>()) << kept;
  }
}

TEST(RenderCommand, BadFovAndPoseAreRejectedWithTheirOptionNamed) {
  std::ostringstream out, err;
  RenderOptions o = small("full");
  o.fov.angles = std::array<double, 4>{20.0, -20.0, 20.0, -20.0};  // left > right
  EXPECT_EQ(run_render(o, out, err), 2);
  EXPECT_NE(err.str().find("--fov-deg: left must be less than right"), std::string::npos) << err.str();
  o = small("full");
  o.pose = std::array<double, 7>{0, 0, 0, 0, 0, 0, 2};  // not a unit quaternion
  EXPECT_EQ(run_render(o, out, err), 2);
  EXPECT_NE(err.str().find("--pose"), std::string::npos) << err.str();

  CLI::App app;
  register_render(app);
  const char* three[] = {"fovea", "render", "--fov-deg", "1,2,3"};
  EXPECT_THROW(app.parse(4, three), CLI::ValidationError);
  CLI::App app2;
  register_render(app2);
  const char* nan_pose[] = {"fovea", "render", "--pose", "0,0,0,0,0,0,nan"};
  EXPECT_THROW(app2.parse(4, nan_pose), CLI::ValidationError);
}

// One spelling per idea in both CLIs: --size WxH and --fov-deg; the old spellings
// (--size W,H, --fov) are errors that name the new one, never a silent alias.
TEST(RenderCommand, OldDisplaySpellingsAreErrorsNamingTheNewOnes) {
  const auto parse_error = [](std::vector<const char*> argv) -> std::string {
    CLI::App app;
    register_render(app);
    try {
      app.parse(static_cast<int>(argv.size()), argv.data());
    } catch (const CLI::RuntimeError&) {
      return "";  // parsed; the run's own exit code
    } catch (const CLI::ParseError& e) {
      return e.what();
    }
    return "";
  };
  EXPECT_NE(parse_error({"fovea", "render", "--fov", "-40,40,40,-40"}).find("--fov-deg"), std::string::npos);
  const std::string comma = parse_error({"fovea", "render", "--size", "16,16"});
  EXPECT_NE(comma.find("expected WxH"), std::string::npos) << comma;
  EXPECT_NE(comma.find("'16,16'"), std::string::npos) << comma;
  EXPECT_NE(parse_error({"fovea", "render", "--size", "0x16"}).find("--size"), std::string::npos);
  EXPECT_EQ(parse_error({"fovea", "render", "--size", "16x18", "--fov-deg", "60", "--frames", "0"}), "")
      << "the new spellings parse (the run then refuses --frames 0)";
}

// --fov-deg H: a symmetric frustum of that horizontal span, its vertical span from the size.
TEST(RenderCommand, OneFovNumberIsTheHorizontalSpan) {
  RenderOptions o = small("full");  // 40x45
  o.fov.horizontal = 60.0;
  std::ostringstream out, err;
  ASSERT_EQ(run_render(o, out, err), 0) << err.str();
  const auto j = nlohmann::json::parse(out.str());
  EXPECT_NEAR(j["fov_deg"][0].get<double>(), -30.0, 1e-4);
  EXPECT_NEAR(j["fov_deg"][1].get<double>(), 30.0, 1e-4);
  const double up = std::atan(std::tan(30.0 * 3.14159265358979 / 180.0) * 45.0 / 40.0) * 180.0 / 3.14159265358979;
  EXPECT_NEAR(j["fov_deg"][2].get<double>(), up, 1e-4);
  EXPECT_NEAR(j["fov_deg"][3].get<double>(), -up, 1e-4);
}

// --fov-deg L,R,U,D / --pose replace the preset's view: echoed in the report, and a camera
// turned around (180 deg about +y) sees another image.
TEST(RenderCommand, FovAndPoseDefineTheView) {
  RenderOptions o = small("full");
  o.out_prefix.clear();
  o.fov.angles = std::array<double, 4>{-40.0, 30.0, 35.0, -45.0};
  o.pose = std::array<double, 7>{0.0, 1.6, 2.0, 0.0, 0.0, 0.0, 1.0};
  std::ostringstream out1, err1;
  ASSERT_EQ(run_render(o, out1, err1), 0) << err1.str();
  const auto a = nlohmann::json::parse(out1.str());
  EXPECT_NEAR(a["fov_deg"][0].get<double>(), -40.0, 1e-4);
  EXPECT_NEAR(a["fov_deg"][3].get<double>(), -45.0, 1e-4);
  EXPECT_NEAR(a["pose"][1].get<double>(), 1.6, 1e-6);
  EXPECT_NEAR(a["pose"][6].get<double>(), 1.0, 1e-6);

  engine_test::TempDir dir;
  auto render_png = [&](const std::array<double, 7>& pose, const char* name) {
    RenderOptions r = o;
    r.pose = pose;
    r.out_prefix = (dir.path / name).string();
    std::ostringstream out, err;
    EXPECT_EQ(run_render(r, out, err), 0) << err.str();
    std::ifstream in(r.out_prefix + "_full.png", std::ios::binary);
    std::ostringstream bytes;
    bytes << in.rdbuf();
    return bytes.str();
  };
  const std::string forward = render_png(*o.pose, "forward");
  const std::string again = render_png(*o.pose, "again");
  const std::string back = render_png({0.0, 1.6, 2.0, 0.0, 1.0, 0.0, 0.0}, "back");
  ASSERT_FALSE(forward.empty());
  EXPECT_EQ(forward, again);  // deterministic
  EXPECT_NE(forward, back);
}

// Foveated NN output at the fovea is close to the full render. Both images are
// 4-sample estimates of the same pixels; what differs is sampling noise and
// NN's nearest-point choice. Stated tolerance, rings 0-2.5 and 2.5-5 deg:
// SSIM >= 0.75 and PSNR >= 15 dB. The gaze rests on the lit, textured mirror
// floor (measured: SSIM 0.98 / 0.98, PSNR 31.6 / 32.1 dB). Scene layout note:
// since the default scene was recomposed, its view centre holds the colonnade,
// whose 0.4 m pillars are 3 px wide at this test's 120 px width, below the point
// spacing outside the fovea (centre: SSIM 0.71 / 0.78, PSNR 8.8 / 11.0 dB:
// aliasing of 3 px features, not the method), and the glass sphere refracts the
// checker floor into detail finer than that spacing (gaze (19, 80): SSIM
// 0.68 / 0.74, PSNR 28.0 / 24.9 dB).
TEST(RenderCommand, BothModeFoveatedMatchesFullAtTheFovea) {
  RenderOptions o = small("both");
  o.size_px = glm::ivec2(120, 135);
  o.gaze_px = glm::vec2(61.0f, 122.0f);  // the floor: (652, 1306) of the 1280x1440 view, scaled
  o.rays_per_point = 4;
  std::ostringstream out, err;
  ASSERT_EQ(run_render(o, out, err), 0) << err.str();
  const auto j = nlohmann::json::parse(out.str());
  EXPECT_GT(j["points"].get<uint64_t>(), 0u);
  EXPECT_EQ(j["foveated"]["rays"]["primary"].get<uint64_t>(), 4 * j["points"].get<uint64_t>());
  EXPECT_GT(j["speedup"].get<double>(), 0.0);
  EXPECT_EQ(j["frames"], 3);  // the default: three interleaved frames per mode, median reported
  EXPECT_EQ(j["full"]["frames_total_ms"].size(), 3u);
  EXPECT_EQ(j["foveated"]["frames_total_ms"].size(), 3u);
  EXPECT_GT(j["content_speedup"].get<double>(), 0.0);
  EXPECT_TRUE(j["overhead_fraction"].is_number());
  // The pixel-exact fovea: inside the pixel grid (the whole of this small
  // view) the foveated image is the full render's, the same rays with the same
  // seed: identical rings (PSNR infinite, written as null; SSIM 1).
  EXPECT_EQ(j["points"].get<uint64_t>(), 120u * 135u);
  ASSERT_GE(j["rings"].size(), 2u);
  for (int r = 0; r < 2; ++r) {
    const auto& ring = j["rings"][r];
    SCOPED_TRACE(ring.dump());
    EXPECT_EQ(ring["from_deg"].get<double>(), r == 0 ? 0.0 : 2.5);
    EXPECT_EQ(ring["ssim"].get<double>(), 1.0);
    EXPECT_TRUE(ring["psnr"].is_null());
  }
}

namespace {

// An engine that answers every ray with the same grey: what is left is the caller's work.
extern "C" int32_t grey_engine(void*, const FoveartRayBatch* batch) {
  for (uint32_t i = 0; i < 3 * batch->ray_count; ++i) batch->out_rgb[i] = 0.5f;
  return FOVEART_RESULT_SUCCESS;
}

}  // namespace

// The one foveated frame as `fovea render` drives it: a frame's image must not
// depend on the frame before it (another gaze) nor on the thread count, and
// (with the 10 px visible margin) every pixel's nearest point is traced, so no
// pixel falls back to black.
TEST(FoveatedRender, FramesAreIndependentOfEarlierFramesAndOfThreads) {
  namespace fv = foveart::foveation;
  std::string error;
  auto tracer = foveart::engine::Tracer::create(foveart::engine::make_default_scene(), {}, &error);
  ASSERT_TRUE(tracer) << error;
  FoveartEyeView view = foveart::engine::fove_eye_view(0, foveart::engine::scene_head(tracer->scene()));
  view.width_px = 96;
  view.height_px = 108;
  engine_test::TempDir cache;  // the second view loads the first one's tables
  fv::PointSetKey key;
  key.display = fv::DisplayModel::from_fov(96, 108, 95.0);
  // At 96 px for 95 degrees the eye resolves every pixel: the whole view would
  // be the pixel grid, the same at any gaze. Scale 8 shrinks the grid to ~24 px.
  key.display.scale = 8.0;
  fv::InterpOptions nn;
  nn.method = fv::InterpMethod::nearest;
  nn.k = 1;
  fv::Executor one_thread(1), three_threads(3);
  fv::ViewSettings settings;
  settings.rays_per_point = 2;
  fv::FoveatedView one(fv::load_view_tables(cache.path, key, nn, one_thread), settings);
  fv::FoveatedView three(fv::load_view_tables(cache.path, key, nn, three_threads), settings);
  EXPECT_TRUE(three.tables().from_cache);

  auto frame = [&](fv::FoveatedView& v, glm::vec2 gaze, FoveartTraceRaysFn fn, void* user, fv::Executor& ex) {
    fv::FrameRequest request;
    request.view = view;
    request.gaze_px = gaze;
    const fv::FrameResult r = v.render(request, fn, user, ex);
    EXPECT_TRUE(r.ok()) << r.message;
    return std::make_pair(r, v.image());
  };
  const glm::vec2 gaze_a(10.0f, 15.0f), gaze_b(70.0f, 80.0f);
  const auto [ra, a] = frame(one, gaze_a, &foveart_engine_trace_rays, tracer.get(), one_thread);
  const auto [rb, b_after_a] = frame(one, gaze_b, &foveart_engine_trace_rays, tracer.get(), one_thread);
  const auto [rf, b_fresh] = frame(three, gaze_b, &foveart_engine_trace_rays, tracer.get(), three_threads);
  EXPECT_GT(ra.points, 0u);
  EXPECT_NE(ra.points, rb.points);  // the gaze moved the visible set
  EXPECT_EQ(ra.gather.fallback, 0u);  // no pixel without a traced point in reach
  // Every traced point falls in one screen tile (margin points in the nearest).
  const auto mapping = fv::map_gaze(96, 108, gaze_a);
  const std::vector<uint32_t> per_tile = fv::points_per_tile(one.tables().points, mapping, 16, 16, 6, 7);
  ASSERT_EQ(per_tile.size(), 42u);
  EXPECT_EQ(std::accumulate(per_tile.begin(), per_tile.end(), uint64_t{0}), ra.points);
  EXPECT_GT(per_tile[0], per_tile[41]);  // gaze (10, 15): dense top-left, sparse bottom-right
  EXPECT_TRUE(fv::points_per_tile(one.tables().points, mapping, 16, 16, 0, 7).empty());  // no grid, no counts
  EXPECT_TRUE(fv::points_per_tile(one.tables().points, mapping, 0, 16, 6, 7).empty());
  ASSERT_EQ(b_after_a.rgb.size(), b_fresh.rgb.size());
  size_t differ_from_a = 0;
  for (size_t i = 0; i < b_fresh.rgb.size(); ++i) {
    ASSERT_EQ(b_after_a.rgb[i], b_fresh.rgb[i]) << "value " << i;
    differ_from_a += a.rgb[i] != b_fresh.rgb[i] ? 1 : 0;
  }
  EXPECT_GT(differ_from_a, b_fresh.rgb.size() / 10);

  const auto [rg, grey] = frame(three, gaze_a, &grey_engine, nullptr, three_threads);
  for (size_t i = 0; i < grey.rgb.size(); ++i) ASSERT_EQ(grey.rgb[i], 0.5f) << "value " << i;
}
