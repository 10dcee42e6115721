// Debian's hello_xr (a real OpenXR client nobody here wrote) against the
// simulated runtime: runs to exit 0 on the frame budget, its captured frames are
// not blank, and the OpenXR core validation and Vulkan validation layers report
// no errors.
#include <gtest/gtest.h>
#include <stb_image.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>

#include "child_process.hpp"
#include "xr_test_app.h"

namespace foveart::sim::test {
namespace {

using foveart::test::ProcessResult;

constexpr int kFrames = 12;

// Runs hello_xr with stdin an open pipe (EOF makes it quit), output to a file.
ProcessResult run_hello_xr(const std::map<std::string, std::string>& extra_env, const std::string& dir) {
  std::map<std::string, std::string> env;
  for (const char* d : {"home", "config", "data", "cache", "runtime"})
    std::filesystem::create_directories(dir + "/" + d);
  env["HOME"] = dir + "/home";
  env["XDG_CONFIG_HOME"] = env["XDG_CONFIG_DIRS"] = dir + "/config";
  env["XDG_DATA_HOME"] = env["XDG_DATA_DIRS"] = dir + "/data";
  env["XDG_CACHE_HOME"] = dir + "/cache";
  env["XDG_RUNTIME_DIR"] = dir + "/runtime";
  env["XR_RUNTIME_JSON"] = FOVEART_SIM_RUNTIME_JSON;
  env["VK_ICD_FILENAMES"] = "/usr/share/vulkan/icd.d/lvp_icd.x86_64.json";
  env["FOVEART_SIM_LOG"] = "1";
  if (std::string(FOVEART_SANITIZER_PRELOAD).size() > 0) {
    env["LD_PRELOAD"] = FOVEART_SANITIZER_PRELOAD;
    env["ASAN_OPTIONS"] =
        "detect_leaks=0:verify_asan_link_order=0";  // hello_xr's own leaks are not ours
  }
  for (const auto& [k, v] : extra_env) env[k] = v;
  const std::vector<std::string> envp = foveart::test::environment_with(env);
  const auto result = foveart::test::run_process({FOVEART_HELLO_XR, "-g", "Vulkan2"}, dir + "/hello_xr.log", 240, &envp);
  EXPECT_FALSE(result.exit_code == -1 && !result.timed_out) << "cannot start " << FOVEART_HELLO_XR;
  return result;
}

// Standard deviation of luma: 0 for a blank image.
double luma_stddev(const std::string& png, int* w, int* h) {
  int comp = 0;
  unsigned char* data = stbi_load(png.c_str(), w, h, &comp, 3);
  if (data == nullptr) return -1.0;
  double sum = 0.0, sum2 = 0.0;
  const size_t n = static_cast<size_t>(*w) * static_cast<size_t>(*h);
  for (size_t i = 0; i < n; ++i) {
    const double y = 0.299 * data[i * 3] + 0.587 * data[i * 3 + 1] + 0.114 * data[i * 3 + 2];
    sum += y;
    sum2 += y * y;
  }
  stbi_image_free(data);
  const double mean = sum / static_cast<double>(n);
  return std::sqrt(std::max(0.0, sum2 / static_cast<double>(n) - mean * mean));
}

size_t count_lines(const std::string& path) {
  std::ifstream in(path);
  size_t n = 0;
  for (std::string line; std::getline(in, line);) ++n;
  return n;
}

class HelloXr : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_FALSE(std::string(FOVEART_HELLO_XR).empty())
        << "hello_xr (libopenxr-utils, installed by scripts/setup.sh) is missing";
  }
};

void expect_capture(const std::string& capture) {
  // Frames 0 and 6 (every 6th), both eyes, 1280x1440, not blank.
  for (const char* name : {"frame_000000_left.png", "frame_000000_right.png",
                           "frame_000006_left.png", "frame_000006_right.png"}) {
    int w = 0, h = 0;
    const double sd = luma_stddev(capture + "/" + name, &w, &h);
    ASSERT_GE(sd, 0.0) << name << " missing or unreadable";
    EXPECT_EQ(w, 1280) << name;
    EXPECT_EQ(h, 1440) << name;
    EXPECT_GT(sd, 2.0) << name << " is blank";
  }
  EXPECT_FALSE(std::filesystem::exists(capture + "/frame_000001_left.png"));
  EXPECT_EQ(count_lines(capture + "/frames.csv"),
            static_cast<size_t>(kFrames) + 1);  // header + one row per frame
}

TEST_F(HelloXr, RunsToCompletionWithinTheFrameBudgetAndShowsFrames) {
  const std::string dir = fresh_dir("run");
  const std::string capture = dir + "/capture";
  const ProcessResult r = run_hello_xr({{"FOVEART_SIM_FRAMES", std::to_string(kFrames)},
                                    {"FOVEART_SIM_CLOCK", "virtual"},
                                    {"FOVEART_SIM_CAPTURE_DIR", capture},
                                    {"FOVEART_SIM_CAPTURE_EVERY", "6"}},
                                   dir);
  ASSERT_FALSE(r.timed_out) << r.output;
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("XR_SESSION_STATE_EXITING"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("foveart-sim [error]"), std::string::npos) << r.output;
  expect_capture(capture);
}

TEST_F(HelloXr, CoreValidationAndVulkanValidationReportNoErrors) {
  const std::string dir = fresh_dir("run");
  const std::string capture = dir + "/capture";
  const ProcessResult r =
      run_hello_xr({{"FOVEART_SIM_FRAMES", std::to_string(kFrames)},
                    {"FOVEART_SIM_CLOCK", "virtual"},
                    {"FOVEART_SIM_CAPTURE_DIR", capture},
                    {"FOVEART_SIM_CAPTURE_EVERY", "6"},
                    {"XR_ENABLE_API_LAYERS", "XR_APILAYER_LUNARG_core_validation"},
                    {"XR_API_LAYER_PATH", "/usr/share/openxr/1/api_layers/explicit.d"},
                    {"VK_INSTANCE_LAYERS", "VK_LAYER_KHRONOS_validation"},
                    {"VK_LAYER_PATH", "/usr/share/vulkan/explicit_layer.d"}},
                   dir);
  ASSERT_FALSE(r.timed_out) << r.output;
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // Both layers really ran: core validation announces itself, and hello_xr's
  // Vulkan debug messenger relays the loader's note that it inserted the Khronos layer.
  EXPECT_NE(r.output.find("Core Validation output type"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("Inserted device layer \"VK_LAYER_KHRONOS_validation\""),
            std::string::npos)
      << r.output;
  // Error markers: core validation text output ("VALID_ERROR", "VUID-"), its
  // internal errors, and Vulkan validation errors ("Validation Error", "ERROR:").
  for (const char* marker : {"VALID_ERROR", "VUID-", "INTERNAL VALIDATION LAYER ERROR",
                             "Validation Error", "ERROR:", "foveart-sim [error]"}) {
    EXPECT_EQ(r.output.find(marker), std::string::npos) << "found '" << marker << "' in:\n"
                                                        << r.output;
  }
  expect_capture(capture);
}

}  // namespace
}  // namespace foveart::sim::test
