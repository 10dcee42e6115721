// `fovea pointset`'s display options: a zero, negative, non-finite or
// out-of-range size, field of view, pixels per degree or scale is an error
// naming the option and the value, with a non-zero exit and nothing written;
// never "unset, take the preset". Runs the fovea binary built next to this
// test (both go to the build's bin/).
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace foveart::fovea {
namespace {

namespace fs = std::filesystem;

struct ToolRun {
  int exit_code = -1;
  std::string out, err;
};

std::string read_all(const fs::path& p) {
  std::ifstream in(p);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

class PointsetOptions : public ::testing::Test {
 protected:
  void SetUp() override {
    fovea_ = fs::read_symlink("/proc/self/exe").parent_path() / "fovea";
    ASSERT_TRUE(fs::exists(fovea_)) << fovea_ << " is missing: build the fovea target";
    dir_ = fs::temp_directory_path() / ("foveart_pointset_cli_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_ / "io");
  }
  void TearDown() override { fs::remove_all(dir_); }

  // Where pointset may write (an existing, empty folder): nothing may appear
  // here when it fails.
  fs::path outputs() const { return dir_ / "outputs"; }

  // fovea pointset with every output option pointed into outputs().
  // png: where --png writes, empty for outputs()/points.png.
  ToolRun pointset(const std::vector<std::string>& args, const std::string& png = "") const {
    std::string cmd = "'" + fovea_.string() + "' pointset --k 1 --json";
    cmd += " --png '" + (png.empty() ? (outputs() / "points.png").string() : png) + "'";
    cmd += " --curves '" + (outputs() / "curves").string() + "'";
    cmd += " --cache-dir '" + (outputs() / "cache").string() + "'";
    for (const auto& a : args) cmd += " '" + a + "'";
    cmd += " >'" + (dir_ / "io" / "out").string() + "' 2>'" + (dir_ / "io" / "err").string() + "'";
    const int status = std::system(cmd.c_str());
    ToolRun r;
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.out = read_all(dir_ / "io" / "out");
    r.err = read_all(dir_ / "io" / "err");
    return r;
  }

  fs::path fovea_, dir_;
};

TEST_F(PointsetOptions, ValidSmallDisplayRunsAndWrites) {
  fs::create_directories(outputs());
  const ToolRun r = pointset({"--size", "64x48", "--fov-deg", "40"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("\"width\": 64"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"height\": 48"), std::string::npos) << r.out;
  EXPECT_TRUE(fs::exists(outputs() / "points.png"));
}

// Below scale 1 the grid widens beyond the pixel-exact fovea, the grid of scale 1; the report
// gives both.
TEST_F(PointsetOptions, ReportsThePixelExactFoveaInsideAWiderGrid) {
  fs::create_directories(outputs());
  auto grid_of = [&](const char* scale) {
    const ToolRun r = pointset({"--size", "128x96", "--pixels-per-degree", "64", "--density-scale", scale});
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return nlohmann::json::parse(r.out, nullptr, false)["pixel_grid"];
  };
  const nlohmann::json denser = grid_of("0.75"), thesis = grid_of("1");
  ASSERT_TRUE(denser.is_object() && thesis.is_object());
  EXPECT_EQ(thesis["exact_fovea"]["points"], thesis["points"]) << "at scale 1 the grid is the fovea";
  EXPECT_EQ(denser["exact_fovea"]["points"], thesis["points"]) << "a denser scale widens the grid, not the fovea";
  EXPECT_EQ(denser["exact_fovea"]["radius_px"], thesis["radius_px"]);
  EXPECT_GT(denser["points"].get<double>(), 1.5 * denser["exact_fovea"]["points"].get<double>());
}

// --fov-deg L,R,U,D: the point set follows the horizontal span, as the layer's.
TEST_F(PointsetOptions, FourFovAnglesGiveTheirHorizontalSpan) {
  fs::create_directories(outputs());
  const ToolRun r = pointset({"--size", "64x48", "--fov-deg", "-25,15,20,-20"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("\"fov_deg\": 40"), std::string::npos) << r.out;
}

TEST_F(PointsetOptions, BadValueIsAnErrorNamingOptionAndValue) {
  struct Case {
    const char* option;
    const char* value;
    std::vector<std::string> rest;  // a small valid display otherwise
  };
  const std::vector<std::string> size = {"--size", "64x48"};
  const std::vector<std::string> display = {"--size", "64x48", "--fov-deg", "40"};
  const std::vector<Case> cases = {
      {"--size", "0x48", {"--fov-deg", "40"}},
      {"--size", "-5x48", {"--fov-deg", "40"}},
      {"--size", "64x0", {"--fov-deg", "40"}},
      {"--size", "64,48", {"--fov-deg", "40"}},  // the old separator
      {"--fov-deg", "0", size},
      {"--fov-deg", "-10", size},
      {"--fov-deg", "180", size},
      {"--fov-deg", "nan", size},
      {"--fov-deg", "10,20", size},
      {"--fov-deg", "20,-20,20,-20", size},  // left > right
      {"--pixels-per-degree", "0", size},
      {"--pixels-per-degree", "-2", size},
      {"--pixels-per-degree", "inf", size},
      {"--density-scale", "0", display},
      {"--density-scale", "-1", display},
      {"--density-scale", "nan", display},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(std::string(c.option) + " " + c.value);
    std::vector<std::string> args = c.rest;
    args.push_back(c.option);
    args.push_back(c.value);
    fs::remove_all(outputs());
    fs::create_directories(outputs());
    const ToolRun r = pointset(args);
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_EQ(r.err.rfind(std::string("fovea pointset: ") + c.option + ": ", 0), 0u) << r.err;
    const std::string value = c.value;
    const bool says_value = r.err.find("got " + value + "\n") != std::string::npos ||
                            r.err.find("got '" + value + "'\n") != std::string::npos;
    if (value != "20,-20,20,-20") {
      EXPECT_TRUE(says_value) << r.err;
    }
    EXPECT_TRUE(r.out.empty()) << r.out;
    EXPECT_TRUE(fs::is_empty(outputs())) << "written despite the error";
  }
}

// The old spellings --width and --height are errors naming --size, not silently taken.
TEST_F(PointsetOptions, OldSizeSpellingsNameTheNewOne) {
  for (const char* old : {"--width", "--height"}) {
    fs::remove_all(outputs());
    fs::create_directories(outputs());
    const ToolRun r = pointset({old, "64"});
    EXPECT_NE(r.exit_code, 0) << old;
    EXPECT_NE(r.err.find(old), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("--size WxH"), std::string::npos) << r.err;
    EXPECT_TRUE(r.out.empty()) << r.out;
  }
}

// An output that cannot be written: exit code 2 and a message naming the file, before any work.
TEST_F(PointsetOptions, UnwritableOutputIsExitCodeTwoNamingTheFile) {
  fs::create_directories(outputs());
  const std::string missing = (dir_ / "no_such_dir" / "points.png").string();
  const ToolRun r = pointset({"--size", "64x48"}, missing);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("fovea pointset: --png: cannot write " + missing), std::string::npos) << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
}

}  // namespace
}  // namespace foveart::fovea
