// One hello_foveated --json process for the tests that drive the layer through the app
// (gpu_engine_run.hpp's GpuEngine, hello_foveated_mode_test.cpp): an isolated environment
// with a static head and no scripted eye tracking, the app's frames captured into
// <root>/<name>, its stats parsed from the JSON it prints last.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "app_output.hpp"
#include "child_process.hpp"
#include "test_env.hpp"

namespace foveart::layer::test {

using foveart::test::ProcessResult;
using foveart::test::run_process;

constexpr int kAppTimeoutS = 600;

struct AppRun {
  ProcessResult process;
  nlohmann::json stats;
  fs::path frames;
};

class HelloFoveatedRun : public ::testing::Test {
 protected:
  // The layer config (configure_hello_foveated's, `reconstruction` its key) and the runtime's setting.
  void set_up(int frames, const char* reconstruction) {
    ASSERT_TRUE(have_runtime()) << "the simulated runtime is part of every build: its manifest is missing";
    env_ = std::make_unique<IsolatedEnv>();
    configure_hello_foveated(*env_, frames, reconstruction);
    IsolatedEnv::set("FOVEART_SIM_HEAD", "static");
    for (const char* name : {"FOVEART_SIM_CAPTURE_EVERY", "FOVEART_SIM_EYE_TRACKING", "FOVEART_SIM_GAZE"}) {
      ::unsetenv(name);
    }
  }

  // The app run with `args` (its path first) for `frames` frames, captured into <root>/<name>.
  AppRun run(const std::string& name, const std::vector<std::string>& args, int frames) const {
    AppRun r;
    r.frames = env_->root() / name;
    IsolatedEnv::set("FOVEART_SIM_CAPTURE_DIR", r.frames);
    IsolatedEnv::set("FOVEART_SIM_FRAMES", std::to_string(frames).c_str());
    r.process = run_process(args, env_->root() / (name + ".log"), kAppTimeoutS);
    r.stats = trailing_json(r.process.output);
    return r;
  }

  static fs::path frame(const AppRun& run, int index, const char* eye) { return captured_frame(run.frames, index, eye); }

  std::unique_ptr<IsolatedEnv> env_;
};

}  // namespace foveart::layer::test
