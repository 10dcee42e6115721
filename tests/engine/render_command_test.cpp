// `fovea render` through its library entry point (run_render) and CLI11.
#include "gltf_fixtures.hpp"

#include <cmd_render.hpp>

#include <CLI/CLI.hpp>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sstream>

using foveart::tools::RenderOptions;
using foveart::tools::run_render;

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

TEST(RenderCommand, WritesPngWithPrefix) {
  engine_test::TempDir dir;
  RenderOptions o = small("full");
  o.spp = 2;
  o.out_prefix = (dir.path / "img").string();
  std::ostringstream out, err;
  ASSERT_EQ(run_render(o, out, err), 0) << err.str();
  EXPECT_TRUE(std::filesystem::exists(dir.path / "img_full.png"));
  EXPECT_GT(std::filesystem::file_size(dir.path / "img_full.png"), 100u);
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
}

TEST(RenderCommand, RegistersWithCli11AndRejectsBadGaze) {
  CLI::App app;
  register_render(app);
  EXPECT_NO_THROW(app.get_subcommand("render"));
  const char* argv[] = {"fovea", "render", "--gaze", "abc", "--size", "16,16"};
  EXPECT_THROW(app.parse(6, argv), CLI::ValidationError);
}

#ifdef FOVEART_HAVE_FOVEATION
// Foveated NN output at the fovea matches the full render: within 2 degrees
// of the gaze the point set has one point per pixel, so NN reconstruction with
// one centred ray per point is close to one jittered ray per pixel.
TEST(RenderCommand, BothModeFoveatedMatchesFullAtTheFovea) {
  RenderOptions o = small("both");
  o.size_px = glm::ivec2(160, 180);
  std::ostringstream out, err;
  ASSERT_EQ(run_render(o, out, err), 0) << err.str();
  const auto j = nlohmann::json::parse(out.str());
  EXPECT_LT(j["points"].get<uint64_t>(), j["pixels"].get<uint64_t>());
  EXPECT_EQ(j["foveated"]["rays"]["primary"], j["points"]);
  ASSERT_TRUE(j.contains("speedup"));
  ASSERT_FALSE(j["rings"].empty());
  const auto& fovea = j["rings"][0];
  EXPECT_EQ(fovea["from_deg"], 0.0);
  // Stated tolerance: SSIM >= 0.6 and PSNR >= 18 dB in the innermost ring.
  EXPECT_GE(fovea["ssim"].get<double>(), 0.6);
  if (!fovea["psnr"].is_null()) {
    EXPECT_GE(fovea["psnr"].get<double>(), 18.0);
  }
}
#endif
