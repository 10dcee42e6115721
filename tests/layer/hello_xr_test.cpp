// Debian's hello_xr (a real OpenXR client nobody here wrote) through the layer
// and the simulated runtime on lavapipe: the layer must be invisible to an app
// that does not opt in, also stacked with the Khronos validation layers.
#include <algorithm>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "layer/XR_FOVEART_foveated_ray_tracing.h"
#include "child_process.hpp"
#include "test_env.hpp"

namespace foveart::layer::test {
namespace {

using foveart::test::ProcessResult;
using foveart::test::run_process;

constexpr int kFrames = 12;
constexpr int kTimeoutS = 240;

std::vector<fs::path> frames_in(const fs::path& dir) {
  std::vector<fs::path> files;
  if (!fs::exists(dir)) return files;
  for (const auto& entry : fs::recursive_directory_iterator(dir)) {
    if (entry.is_regular_file()) files.push_back(fs::relative(entry.path(), dir));
  }
  std::sort(files.begin(), files.end());
  return files;
}

std::string read_all(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

ProcessResult run_hello_xr(const IsolatedEnv& env, const std::string& tag, const fs::path& capture_dir) {
  fs::create_directories(capture_dir);
  IsolatedEnv::set("FOVEART_SIM_CAPTURE_DIR", capture_dir);
  IsolatedEnv::set("FOVEART_SIM_FRAMES", std::to_string(kFrames).c_str());
#ifdef FOVEART_TEST_ASAN_RUNTIME
  // hello_xr is not instrumented; the sanitized layer/runtime need the ASan runtime first.
  IsolatedEnv::set("LD_PRELOAD", FOVEART_TEST_ASAN_RUNTIME);
#endif
  auto result = run_process({"hello_xr", "-g", "Vulkan2"}, env.root() / (tag + ".log"), kTimeoutS);
  ::unsetenv("LD_PRELOAD");
  return result;
}

class HelloXr : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(have_runtime()) << "the simulated runtime is part of every build: its manifest is missing";
    ASSERT_TRUE(fs::exists("/usr/bin/hello_xr")) << "hello_xr (libopenxr-utils, installed by scripts/setup.sh) is missing";
  }
};

TEST_F(HelloXr, ThroughTheLayerFramesAreBitIdentical) {
  IsolatedEnv env;
  const auto plain = run_hello_xr(env, "plain", env.root() / "frames_plain");
  ASSERT_EQ(plain.exit_code, 0) << plain.output;
  IsolatedEnv::set("XR_ENABLE_API_LAYERS", XR_FOVEART_API_LAYER_NAME);
  IsolatedEnv::set("FOVEART_CONFIG", env.root() / "none.json");  // absent: defaults
  const auto layered = run_hello_xr(env, "layered", env.root() / "frames_layered");
  ASSERT_EQ(layered.exit_code, 0) << layered.output;

  const auto a = frames_in(env.root() / "frames_plain");
  const auto b = frames_in(env.root() / "frames_layered");
  ASSERT_FALSE(a.empty()) << "the runtime captured no frames";
  ASSERT_EQ(a, b);
  for (const auto& f : a) {
    EXPECT_TRUE(read_all(env.root() / "frames_plain" / f) == read_all(env.root() / "frames_layered" / f))
        << f << " differs with the layer";
  }
}

TEST_F(HelloXr, StackedWithValidationLayersReportsNoErrors) {
  IsolatedEnv env;
  IsolatedEnv::set("XR_API_LAYER_PATH",
                   (explicit_layer_dir().string() + ":" + kSystemExplicitLayers).c_str());
  IsolatedEnv::set("XR_ENABLE_API_LAYERS",
                   (std::string("XR_APILAYER_LUNARG_core_validation:") + XR_FOVEART_API_LAYER_NAME).c_str());
  IsolatedEnv::set("VK_INSTANCE_LAYERS", "VK_LAYER_KHRONOS_validation");
  IsolatedEnv::set("VK_LAYER_PATH", "/usr/share/vulkan/explicit_layer.d");
  // Loader logs prove the validation layers were really in the chain.
  IsolatedEnv::set("XR_LOADER_DEBUG", "info");
  IsolatedEnv::set("VK_LOADER_DEBUG", "layer");
  const auto run = run_hello_xr(env, "validated", env.root() / "frames");
  for (const char* name : {"VK_INSTANCE_LAYERS", "VK_LAYER_PATH", "XR_LOADER_DEBUG", "VK_LOADER_DEBUG"}) {
    ::unsetenv(name);
  }
  ASSERT_EQ(run.exit_code, 0) << run.output;
  for (const char* loaded : {"succeeded loading layer XR_APILAYER_LUNARG_core_validation",
                             "succeeded loading layer XR_APILAYER_FOVEART_foveated_ray_tracing",
                             "Insert instance layer \"VK_LAYER_KHRONOS_validation\""}) {
    EXPECT_NE(run.output.find(loaded), std::string::npos) << "missing: " << loaded;
  }
  for (const char* marker : {"Validation Error", "VUID-", "VALID_USAGE", "XR_ERROR"}) {
    EXPECT_EQ(run.output.find(marker), std::string::npos) << marker << " in:\n" << run.output;
  }
  EXPECT_FALSE(frames_in(env.root() / "frames").empty());
}

}  // namespace
}  // namespace foveart::layer::test
