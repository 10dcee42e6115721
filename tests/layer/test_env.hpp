// Isolated environment for headless OpenXR tests: private HOME and XDG
// directories, the layer's explicit manifest, the simulated runtime, lavapipe.
#pragma once

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace foveart::layer::test {

namespace fs = std::filesystem;

inline fs::path manifest_dir() { return FOVEART_MANIFEST_DIR; }
inline fs::path runtime_manifest() { return manifest_dir() / "foveart_sim_runtime.json"; }
inline fs::path explicit_layer_dir() { return manifest_dir() / "explicit"; }
inline fs::path implicit_layer_manifest() {
  return manifest_dir() / "implicit" / "XR_APILAYER_FOVEART_foveated_ray_tracing.json";
}
inline const char* kLavapipeIcd = "/usr/share/vulkan/icd.d/lvp_icd.x86_64.json";
inline const char* kSystemExplicitLayers = "/usr/share/openxr/1/api_layers/explicit.d";

// A fresh directory tree per test, removed at the end; sets the process
// environment so the loader sees nothing of the machine's configuration.
class IsolatedEnv {
 public:
  IsolatedEnv() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    root_ = fs::temp_directory_path() /
            ("foveart_layer_" + std::string(info->test_suite_name()) + "_" + info->name() + "_" +
             std::to_string(::getpid()));
    fs::remove_all(root_);
    for (const char* d : {"home", "config", "data", "cache", "config_dirs", "data_dirs", "runtime"}) {
      fs::create_directories(root_ / d);
    }
    set("HOME", root_ / "home");
    set("XDG_CONFIG_HOME", root_ / "config");
    set("XDG_DATA_HOME", root_ / "data");
    set("XDG_CACHE_HOME", root_ / "cache");
    set("XDG_CONFIG_DIRS", root_ / "config_dirs");
    set("XDG_DATA_DIRS", root_ / "data_dirs");
    set("XDG_RUNTIME_DIR", root_ / "runtime");
    set("XR_API_LAYER_PATH", explicit_layer_dir());
    set("XR_RUNTIME_JSON", runtime_manifest());
    set("VK_ICD_FILENAMES", kLavapipeIcd);
    set("FOVEART_SIM_CLOCK", "virtual");
    for (const char* name : {"XR_ENABLE_API_LAYERS", "FOVEART_CONFIG", "FOVEART_DISABLE",
                             "FOVEART_ENABLE_IMPLICIT_LAYER", "FOVEART_DISABLE_IMPLICIT_LAYER",
                             "VK_INSTANCE_LAYERS"}) {
      ::unsetenv(name);
    }
  }
  ~IsolatedEnv() {
    std::error_code ec;
    fs::remove_all(root_, ec);
  }
  IsolatedEnv(const IsolatedEnv&) = delete;
  IsolatedEnv& operator=(const IsolatedEnv&) = delete;

  const fs::path& root() const { return root_; }
  static void set(const char* name, const fs::path& value) { ::setenv(name, value.c_str(), 1); }
  static void set(const char* name, const char* value) { ::setenv(name, value, 1); }

 private:
  fs::path root_;
};

inline bool have_runtime() { return fs::exists(runtime_manifest()); }

#ifdef FOVEART_TEST_CACHE_DIR
// hello_foveated runs: a layer config that waits for the tables (cached once
// for the whole suite), reconstructs where `reconstruction` says (auto | gpu |
// cpu), captures into <root>/frames and runs `frames` frames.
// temporal: the config's "temporal" (empty: its default).
// extra_keys: more of the config's keys, as JSON members ("\"gaze_clock\": \"display_time\"").
inline void configure_hello_foveated(const IsolatedEnv& env, int frames, const char* reconstruction = "auto",
                                     const std::string& temporal = {}, const std::string& extra_keys = {}) {
  const auto config = env.root() / "config.json";
  std::ofstream(config) << R"({"wait_for_tables": true, "cache_dir": ")" << FOVEART_TEST_CACHE_DIR
                        << R"(", "log_level": "info", "reconstruction": ")" << reconstruction << '"'
                        << (temporal.empty() ? "" : R"(, "temporal": ")" + temporal + '"')
                        << (extra_keys.empty() ? "" : ", " + extra_keys) << "}";
  IsolatedEnv::set("FOVEART_CONFIG", config);
  IsolatedEnv::set("FOVEART_SIM_CAPTURE_DIR", env.root() / "frames");
  IsolatedEnv::set("FOVEART_SIM_FRAMES", std::to_string(frames).c_str());
}
#endif

#define FOVEART_REQUIRE_RUNTIME()                                                                  \
  do {                                                                                             \
    ASSERT_TRUE(::foveart::layer::test::have_runtime()) << "the simulated runtime's manifest is missing"; \
  } while (0)

}  // namespace foveart::layer::test
