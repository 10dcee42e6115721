// `fovea render --engine cpu|gpu`: the GPU sample engine behind the callback
// (gpu_engine::CallbackAdapter) renders the same images as the CPU engine, ring
// by ring, and the report says which engine and device traced; a bad --engine
// is refused. Runs on lavapipe; skipped without a Vulkan device.
#include <cmd_render.hpp>
#include <render_view/render_options.hpp>

#include <engine/default_scene.hpp>
#include <engine/render.hpp>
#include <metrics/image_metrics.hpp>
#include <foveation/executor.hpp>
#include <gpu_engine/callback_adapter.hpp>
#include <toolkit/image_io.hpp>

#include "gltf_fixtures.hpp"

#include <CLI/CLI.hpp>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sys/wait.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace fs = std::filesystem;
using foveart::render_view::RenderOptions;
using foveart::fovea::register_render;
using foveart::fovea::run_render;

namespace {

bool have_vulkan_device(std::string* why) {
  static const bool ok = [&] {
    return foveart::gpu_engine::CallbackAdapter::create(foveart::engine::Scene{}, why) != nullptr;
  }();
  return ok;
}

std::string read_all(const fs::path& p) {
  std::ifstream in(p);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

struct ToolRun {
  int exit_code = -1;
  std::string out, err;
};

// The fovea binary beside this test, `args` appended, `env` (VAR=value ...) before it.
ToolRun fovea(const std::string& args, const fs::path& dir, const std::string& env = "") {
  const fs::path exe = fs::read_symlink("/proc/self/exe").parent_path() / "fovea";
  const std::string cmd = env + " '" + exe.string() + "' render " + args + " >'" + (dir / "out").string() + "' 2>'" +
                          (dir / "err").string() + "'";
  const int status = std::system(cmd.c_str());
  ToolRun r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = read_all(dir / "out");
  r.err = read_all(dir / "err");
  return r;
}

constexpr int kWidth = 160, kHeight = 180;

// Per eccentricity ring, the PSNR of two engines' PNGs of the same options
// (display values, peak 1). Measured on lavapipe against Embree (the two tests
// below, 160x180): rings 0-4 identical, the worst ring 78.5 dB (ring 5, 11256
// px: about 30 of its 33768 channel values one 8-bit step apart, the rest
// equal), the thesis pattern 85-88 dB. Every ray within kRayTolerance of the
// CPU's (tests/engine/ray_agreement.hpp) leaves 8-bit rounding as the only
// difference. kAgreeDb = 60 dB (an MSE of 1e-6) is 70x the worst ring's MSE
// and still lets float differences on another machine round a few values the
// other way in the 32-pixel ring 0 (one step there alone is 67.9 dB); every
// value one step off is 48 dB.
constexpr double kAgreeDb = 60.0;
// What a wrong ray layout gives, the control below: measured 4-8 dB per ring.
constexpr double kControlDb = 20.0;

// PSNR per eccentricity ring (pixels in the ring, dB) of two PNGs of the view of `o` (gaze at the centre).
std::vector<std::pair<uint64_t, double>> ring_psnr(const RenderOptions& o, const fs::path& a_png, const fs::path& b_png,
                                                   const char* what) {
  const FoveartEyeView view = foveart::render_view::eye_view(o, foveart::engine::make_default_scene());
  const foveart::metrics::EccentricityMap map =
      foveart::metrics::eccentricity_map(view, glm::vec2(0.5f * kWidth, 0.5f * kHeight));
  foveart::foveation::ImageRgb a, b;
  std::string e;
  std::vector<std::pair<uint64_t, double>> rings;
  EXPECT_TRUE(foveart::toolkit::read_image(a_png.string(), foveart::toolkit::PngValues::display, &a, &e)) << e;
  EXPECT_TRUE(foveart::toolkit::read_image(b_png.string(), foveart::toolkit::PngValues::display, &b, &e)) << e;
  if (!e.empty()) return rings;
  const auto mse = foveart::metrics::ring_mse(a, b, map);
  for (size_t r = 0; r < mse.size(); ++r) {
    const double psnr = mse[r] > 0.0 ? 10.0 * std::log10(1.0 / mse[r]) : std::numeric_limits<double>::infinity();
    rings.emplace_back(map.ring_pixels[r], psnr);
    if (map.ring_pixels[r] == 0) continue;
    std::printf("[ rings ] %s ring %zu (%llu px): PSNR %.1f dB\n", what, r,
                static_cast<unsigned long long>(map.ring_pixels[r]), psnr);
  }
  return rings;
}

// Each ring of the CPU and the GPU engine's PNGs >= kAgreeDb.
void expect_rings_agree(const RenderOptions& o, const fs::path& cpu_png, const fs::path& gpu_png, const char* what) {
  const auto rings = ring_psnr(o, cpu_png, gpu_png, what);
  ASSERT_FALSE(rings.empty());
  for (size_t r = 0; r < rings.size(); ++r) {
    if (rings[r].first > 0) {
      EXPECT_GE(rings[r].second, kAgreeDb) << what << " ring " << r;
    }
  }
}

// The GPU engine handed each batch's rays in a wrong layout: interleaved
// (x, y, z per ray) arrays read as planar (every x, then every y, then every z).
int32_t trace_rays_read_as_planar(void* adapter, const FoveartRayBatch* batch) {
  const size_t n = batch->ray_count;
  auto planar = [n](const float* interleaved, size_t components) {
    std::vector<float> out;
    if (interleaved == nullptr) return out;
    out.resize(components * n);
    for (size_t i = 0; i < n; ++i)
      for (size_t c = 0; c < components; ++c) out[components * i + c] = interleaved[c * n + i];
    return out;
  };
  const std::vector<float> origins = planar(batch->origins_m, 3), directions = planar(batch->directions, 3),
                           sample_px = planar(batch->sample_px, 2);
  FoveartRayBatch wrong = *batch;
  if (batch->origins_m != nullptr) wrong.origins_m = origins.data();
  if (batch->directions != nullptr) wrong.directions = directions.data();
  if (batch->sample_px != nullptr) wrong.sample_px = sample_px.data();
  return foveart_gpu_engine_trace_rays(adapter, &wrong);
}

}  // namespace

// The GPU run through the binary, the CPU run of the same options in process:
// both PNGs (8-bit display values) agree per eccentricity ring, >= kAgreeDb
// (a pixel is 1 ray here). The control: the same full render with the GPU
// engine's rays handed over in a wrong layout is < kControlDb in every ring.
TEST(RenderEngine, GpuEngineBothModeMatchesTheCpuEnginePerRing) {
  std::string why;
  if (!have_vulkan_device(&why)) GTEST_SKIP() << "no Vulkan device: " << why;
  engine_test::TempDir dir;
  const std::string size = std::to_string(kWidth) + "x" + std::to_string(kHeight);
  const ToolRun gpu = fovea("--engine gpu --mode both --json --frames 1 --threads 2 --size " + size + " --out '" +
                                (dir.path / "gpu").string() + "'",
                            dir.path);
  ASSERT_EQ(gpu.exit_code, 0) << gpu.err;
  const auto j = nlohmann::json::parse(gpu.out);
  EXPECT_EQ(j["engine"], "gpu");
  ASSERT_TRUE(j.contains("gpu_device"));
  EXPECT_FALSE(j["gpu_device"].get<std::string>().empty());
  EXPECT_EQ(j["full"]["rays"]["primary"], kWidth * kHeight);
  EXPECT_GT(j["full"]["rays"]["shadow"].get<uint64_t>(), 0u);
  EXPECT_GT(j["full"]["rays"]["reflection"].get<uint64_t>(), 0u);
  EXPECT_GT(j["full"]["rays"]["refraction"].get<uint64_t>(), 0u);
  EXPECT_TRUE(j["full"]["lanes_per_packet"].is_null());  // no Embree packets on the GPU
  EXPECT_EQ(j["foveated"]["rays"]["primary"], j["points"]);
  EXPECT_GT(j["speedup"].get<double>(), 0.0);
  ASSERT_EQ(j["images"].size(), 3u) << "full, foveated and the foveated frame's rays map";
  EXPECT_EQ(j["images"][2], (dir.path / "gpu_rays.png").string()) << "the GPU engine is traced through the CPU trace";

  RenderOptions o;
  o.mode = "both";
  o.size_px = glm::ivec2(kWidth, kHeight);
  o.frames = 1;
  o.threads = 2;
  o.json = true;
  o.out_prefix = (dir.path / "cpu").string();
  std::ostringstream out, err;
  ASSERT_EQ(run_render(o, out, err), 0) << err.str();
  const auto c = nlohmann::json::parse(out.str());
  EXPECT_EQ(c["engine"], "cpu");
  EXPECT_FALSE(c.contains("gpu_device"));
  EXPECT_EQ(c["points"], j["points"]);
  // The exposure is metered through each engine: the same to well under 1%.
  const double ce = c["display"]["exposure"].get<double>(), ge = j["display"]["exposure"].get<double>();
  EXPECT_NEAR(ge, ce, 1e-3 * ce);

  for (const char* which : {"_foveated.png", "_full.png"})
    expect_rings_agree(o, dir.path / (std::string("cpu") + which), dir.path / (std::string("gpu") + which), which);

  // The control: the full render through the GPU engine in process, its rays
  // in a wrong layout, written as the binary writes its PNG.
  std::string error;
  auto adapter = foveart::gpu_engine::CallbackAdapter::create(foveart::engine::make_default_scene(), &error);
  ASSERT_NE(adapter, nullptr) << error;
  const FoveartEyeView view = foveart::render_view::eye_view(o, foveart::engine::make_default_scene());
  foveart::engine::RenderSettings settings;
  settings.spp = o.rays_per_point;
  settings.seed = o.seed;
  settings.pixel_filter = o.pixel_filter;
  foveart::foveation::ImageRgb wrong(1, 1);
  foveart::foveation::Executor executor(2);
  const foveart::engine::RenderResult rendered =
      foveart::engine::render_full(&trace_rays_read_as_planar, adapter.get(), view, settings, &wrong, executor);
  ASSERT_EQ(rendered.status, FOVEART_RESULT_SUCCESS);
  foveart::foveation::DisplayTransform display;
  display.exposure = static_cast<float>(ge);
  display.tone_map = *foveart::foveation::parse_tone_map(o.tone_map);
  const fs::path wrong_png = dir.path / "wrong_layout_full.png";
  ASSERT_TRUE(foveart::toolkit::write_png(wrong_png.string(), wrong, display, &error)) << error;
  const auto rings = ring_psnr(o, dir.path / "cpu_full.png", wrong_png, "control: wrong ray layout, _full.png");
  ASSERT_FALSE(rings.empty());
  for (size_t r = 0; r < rings.size(); ++r) {
    if (rings[r].first > 0) {
      EXPECT_LT(rings[r].second, kControlDb) << "the control passes the ring check: ring " << r;
    }
  }
}

// The thesis pattern (Poisson points everywhere, 69664 of them at this size,
// none on a pixel centre): the reconstruction blends GPU colours as it blends
// the CPU's. In process, both engines.
TEST(RenderEngine, GpuEngineFoveatedThesisPatternMatchesTheCpuEnginePerRing) {
  std::string why;
  if (!have_vulkan_device(&why)) GTEST_SKIP() << "no Vulkan device: " << why;
  engine_test::TempDir dir;
  RenderOptions o;
  o.mode = "foveated";
  o.pattern = "thesis";
  o.size_px = glm::ivec2(kWidth, kHeight);
  o.frames = 1;
  o.threads = 2;
  o.json = true;
  uint64_t points[2] = {0, 0};
  for (const char* engine : {"cpu", "gpu"}) {
    o.engine = engine;
    o.out_prefix = (dir.path / engine).string();
    std::ostringstream out, err;
    ASSERT_EQ(run_render(o, out, err), 0) << engine << ": " << err.str();
    const auto j = nlohmann::json::parse(out.str());
    EXPECT_EQ(j["engine"], engine);
    points[o.engine == "gpu"] = j["points"].get<uint64_t>();
  }
  EXPECT_EQ(points[0], points[1]);
  EXPECT_GT(points[0], uint64_t{kWidth} * kHeight);  // not the pixel grid
  expect_rings_agree(o, dir.path / "cpu_foveated.png", dir.path / "gpu_foveated.png", "thesis foveated");
}

TEST(RenderEngine, TextReportNamesTheEngine) {
  std::string why;
  if (!have_vulkan_device(&why)) GTEST_SKIP() << "no Vulkan device: " << why;
  RenderOptions o;
  o.engine = "gpu";
  o.size_px = glm::ivec2(32, 36);
  o.frames = 1;
  o.threads = 2;
  std::ostringstream out, err;
  ASSERT_EQ(run_render(o, out, err), 0) << err.str();
  EXPECT_NE(out.str().find("engine gpu ("), std::string::npos) << out.str();
}

// An exposure outside (0, kMaxExposure] is refused, and the message names the bound.
TEST(RenderEngine, ExposureOutOfRangeIsRefusedWithItsBound) {
  for (const char* bad : {"0", "-1", "nan", "2e6", "bright"}) {
    RenderOptions o;
    o.exposure = bad;
    o.size_px = glm::ivec2(16, 16);
    std::ostringstream out, err;
    EXPECT_EQ(run_render(o, out, err), 2) << bad;
    EXPECT_NE(err.str().find("--exposure must be auto or a number in (0, 1000000], got '" + std::string(bad) + "'"),
              std::string::npos)
        << err.str();
  }
}

// More threads than an executor runs is refused with a message (it aborted the process when the
// system refused a thread).
TEST(RenderEngine, ThreadsBeyondTheExecutorsMostAreRefused) {
  for (int bad : {-1, 257, 100000}) {
    RenderOptions o;
    o.threads = bad;
    o.size_px = glm::ivec2(16, 16);
    std::ostringstream out, err;
    EXPECT_EQ(run_render(o, out, err), 2) << bad;
    EXPECT_NE(err.str().find("--threads must be in 0..256 (0: all cores), got " + std::to_string(bad)),
              std::string::npos)
        << err.str();
  }
}

// A viewer beyond any scene is refused before the engine sees it (Embree aborted on its rays).
TEST(RenderEngine, APoseBeyondAnySceneIsRefused) {
  RenderOptions standing, exact;
  standing.viewer_m = std::array<double, 3>{1e30, 0.0, 0.0};
  exact.pose = std::array<double, 7>{0.0, 1.6, -2e9, 0.0, 0.0, 0.0, 1.0};
  for (RenderOptions* o : {&standing, &exact}) {
    o->size_px = glm::ivec2(16, 16);
    std::ostringstream out, err;
    EXPECT_EQ(run_render(*o, out, err), 2);
    EXPECT_NE(err.str().find("--pose: the position must be finite and within 1e+09 m of the origin"), std::string::npos)
        << err.str();
  }
}

TEST(RenderEngine, BogusEngineAndNoDeviceAreRefusedWithAMessage) {
  RenderOptions o;
  o.engine = "bogus";
  o.size_px = glm::ivec2(16, 16);
  std::ostringstream out, err;
  EXPECT_EQ(run_render(o, out, err), 2);
  EXPECT_NE(err.str().find("--engine must be cpu or gpu"), std::string::npos) << err.str();
  // And through the binary.
  engine_test::TempDir dir;
  const ToolRun r = fovea("--engine bogus --size 16x16", dir.path);
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("--engine must be cpu or gpu"), std::string::npos) << r.err;
  // No Vulkan driver to be found: a clear error, exit 1.
  const ToolRun none = fovea("--engine gpu --size 16x16", dir.path,
                             "VK_ICD_FILENAMES=/nonexistent/icd.json VK_DRIVER_FILES=/nonexistent/icd.json");
  EXPECT_EQ(none.exit_code, 1);
  EXPECT_NE(none.err.find("fovea render: --engine gpu: "), std::string::npos) << none.err;
  // --help names the option.
  const ToolRun help = fovea("--help", dir.path);
  EXPECT_EQ(help.exit_code, 0);
  EXPECT_NE(help.out.find("--engine"), std::string::npos);
}

TEST(RenderEngine, CpuIsTheDefault) {
  CLI::App app;
  register_render(app);
  CLI::Option* opt = app.get_subcommand("render")->get_option("--engine");
  ASSERT_NE(opt, nullptr);
  EXPECT_EQ(opt->get_default_str(), "cpu");
}
