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
  ToolRun pointset(const std::vector<std::string>& args) const {
    std::string cmd = "'" + fovea_.string() + "' pointset --k 1 --json";
    cmd += " --png '" + (outputs() / "points.png").string() + "'";
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
  const ToolRun r = pointset({"--width", "64", "--height", "48", "--fov-deg", "40"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("\"width\": 64"), std::string::npos) << r.out;
  EXPECT_TRUE(fs::exists(outputs() / "points.png"));
}

TEST_F(PointsetOptions, BadValueIsAnErrorNamingOptionAndValue) {
  struct Case {
    const char* option;
    const char* value;
    std::vector<std::string> rest;  // a small valid display otherwise
  };
  const std::vector<std::string> size = {"--width", "64", "--height", "48"};
  const std::vector<Case> cases = {
      {"--width", "0", {"--height", "48", "--fov-deg", "40"}},
      {"--width", "-5", {"--height", "48", "--fov-deg", "40"}},
      {"--height", "0", {"--width", "64", "--fov-deg", "40"}},
      {"--fov-deg", "0", size},
      {"--fov-deg", "-10", size},
      {"--fov-deg", "180", size},
      {"--fov-deg", "nan", size},
      {"--pixels-per-degree", "0", size},
      {"--pixels-per-degree", "-2", size},
      {"--pixels-per-degree", "inf", size},
      {"--density-scale", "0", {"--width", "64", "--height", "48", "--fov-deg", "40"}},
      {"--density-scale", "-1", {"--width", "64", "--height", "48", "--fov-deg", "40"}},
      {"--density-scale", "nan", {"--width", "64", "--height", "48", "--fov-deg", "40"}},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(std::string(c.option) + " " + c.value);
    std::vector<std::string> args = c.rest;
    args.push_back(c.option);
    args.push_back(c.value);
    fs::remove_all(outputs());
    fs::create_directories(outputs());
    const ToolRun r = pointset(args);
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.err.find(c.option), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(std::string("got ") + c.value + "\n"), std::string::npos) << r.err;
    EXPECT_TRUE(r.out.empty()) << r.out;
    EXPECT_TRUE(fs::is_empty(outputs())) << "written despite the error";
  }
}

}  // namespace
}  // namespace foveart::fovea
