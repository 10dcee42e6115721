// `fovea-eval accuracy`: the errors of one still view against a converged
// reference or a reference image, per ring, saying which reference; the
// reference renders what the image renders (--without too); bad references
// and options are errors naming them.
#include "gltf_fixtures.hpp"

#include <eval/cmd_accuracy.hpp>
#include <eval/pfm.hpp>

#include <metrics/image_metrics.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <sstream>

namespace fs = std::filesystem;
using namespace foveart;

namespace {

eval::AccuracyOptions small(const std::string& mode) {
  eval::AccuracyOptions o;
  o.render.mode = mode;
  o.render.size_px = glm::ivec2(40, 45);
  o.render.threads = 2;
  o.render.json = true;
  o.render.frames = 1;
  return o;
}

nlohmann::json run_json(const eval::AccuracyOptions& o) {
  std::ostringstream out, err;
  const int code = eval::run_accuracy(o, out, err);
  EXPECT_EQ(code, 0) << err.str();
  return code == 0 ? nlohmann::json::parse(out.str()) : nlohmann::json();
}

}  // namespace

TEST(AccuracyCommand, ReportsErrorsAgainstAReferenceAndSaysWhichOne) {
  engine_test::TempDir dir;
  eval::AccuracyOptions o = small("both");
  o.reference.spp = "16";
  o.render.cache_dir = dir.path.string();
  const auto j = run_json(o);
  const auto& a = j["errors_against_reference"];
  EXPECT_EQ(a["reference"]["source"], "converged full render");
  EXPECT_EQ(a["reference"]["spp"], 16);
  EXPECT_EQ(a["reference"]["residual_psnr"].size(), metrics::kRingCount);
  ASSERT_EQ(a["full"]["rings"].size(), metrics::kRingCount);
  ASSERT_EQ(a["foveated"]["rings"].size(), metrics::kRingCount);
  EXPECT_TRUE(a["full"]["rings"][0]["psnr"].is_number());
  EXPECT_TRUE(fs::exists(dir.path / "reference"));

  // A PFM reference of another size, no reference, a bad count: clear errors.
  foveation::ImageRgb tiny(4, 4);
  std::string error;
  ASSERT_TRUE(eval::write_pfm((dir.path / "tiny.pfm").string(), tiny, &error)) << error;
  o.reference.spp.clear();
  o.reference.file = (dir.path / "tiny.pfm").string();
  std::ostringstream out2, err2;
  EXPECT_EQ(eval::run_accuracy(o, out2, err2), 1);
  EXPECT_NE(err2.str().find("tiny.pfm is 4x4"), std::string::npos) << err2.str();
  o.reference.file.clear();
  std::ostringstream out3, err3;
  EXPECT_EQ(eval::run_accuracy(o, out3, err3), 2);
  EXPECT_NE(err3.str().find("--reference-spp"), std::string::npos) << err3.str();
  o.reference.spp = "7";
  std::ostringstream out4, err4;
  EXPECT_EQ(eval::run_accuracy(o, out4, err4), 2);
  EXPECT_NE(err4.str().find("--reference-spp"), std::string::npos) << err4.str();
  EXPECT_EQ(err4.str().rfind("fovea-eval accuracy: ", 0), 0u) << err4.str();
}

// The reference renders what the image renders: with effects left out it is
// rendered again (its own cache file), not read from the whole scene's.
TEST(AccuracyCommand, WithoutLeavesEffectsOutOfTheReferenceToo) {
  engine_test::TempDir dir;
  eval::AccuracyOptions o = small("full");
  o.reference.spp = "4";
  o.reference.cache = dir.path.string();
  const auto every = run_json(o);
  o.render.without = "reflection,refraction";
  const auto without = run_json(o);
  EXPECT_EQ(without["effects"], "shadows+textures");
  EXPECT_FALSE(without["errors_against_reference"]["reference"]["from_cache"].get<bool>());
  EXPECT_NE(without["errors_against_reference"]["reference"]["cache_file"],
            every["errors_against_reference"]["reference"]["cache_file"]);
  EXPECT_TRUE(run_json(o)["errors_against_reference"]["reference"]["from_cache"].get<bool>());
}

// One still view has one TAA mode, and TAA needs the foveated view.
TEST(AccuracyCommand, TaaIsOneModeOfTheFoveatedView) {
  eval::AccuracyOptions o = small("full");
  o.reference.spp = "4";
  o.taa = "reproject";
  std::ostringstream out, err;
  EXPECT_EQ(eval::run_accuracy(o, out, err), 2);
  EXPECT_NE(err.str().find("--taa needs --mode foveated or both"), std::string::npos) << err.str();
  o.render.mode = "foveated";
  o.taa = "off,reproject";
  std::ostringstream out2, err2;
  EXPECT_EQ(eval::run_accuracy(o, out2, err2), 2);
  EXPECT_NE(err2.str().find("one TAA mode"), std::string::npos) << err2.str();
}
