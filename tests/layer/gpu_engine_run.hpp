// hello_foveated --engine gpu runs for the tests of the GPU sample engine
// through the layer (gpu_engine_test.cpp, app_trace_test.cpp): the setting
// (small eyes, a scripted constant gaze, temporal "off"), a run's stats and
// captured frames, and what a clean run must show. The setting's reasons and
// the tolerance of the comparisons: gpu_engine_test.cpp.
#pragma once

#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "hello_foveated_run.hpp"

namespace foveart::layer::test {

constexpr int kWidth = 320, kHeight = 360;  // small eyes: lavapipe traces them in seconds
constexpr int kFrames = 2;                  // the first may come before the replay's first gaze sample
// Two rays per point: the device resolve averages them in its own order.
constexpr int kRaysPerPoint = 2;
// The layer config that turns content density off: the GPU path thins by default, and rays per
// point vary by contrast wherever a point casts several.
constexpr const char* kContentDensityOff = R"("content_contrast": 0, "content_rays": 0)";
// The scripted gaze, FOVE head space (+z forward): about 7 deg right, 4 deg down.
constexpr double kGaze[3] = {0.12, -0.07, 0.99};

class GpuEngine : public HelloFoveatedRun {
 protected:
  void SetUp() override { set_up(kFrames, "gpu"); }

  // A constant scripted gaze (3 min at 120 Hz) in its own file.
  fs::path gaze_trace(const std::string& name, double gx, double gy, double gz) const {
    const auto trace = env_->root() / (name + ".csv");
    std::ofstream csv(trace);
    csv.precision(17);
    csv << "device_time_us,frame_id,valid,gaze_x,gaze_y,gaze_z\n";
    for (int i = 0; i < 21600; ++i) csv << i * 8333 << "," << i << ",1," << gx << "," << gy << "," << gz << "\n";
    return trace;
  }

  // hello_foveated with the scripted gaze, its frames captured into <root>/<name>.
  AppRun launch(const std::string& name, const std::string& engine, const fs::path& gaze,
                std::vector<std::string> extra = {}, int frames = kFrames, int rays_per_point = kRaysPerPoint,
                const std::string& temporal = "off") {
    std::vector<std::string> args{FOVEART_HELLO_FOVEATED, "--json", "--engine", engine, "--eye-size",
                                  std::to_string(kWidth), std::to_string(kHeight), "--interpolation", "msm", "--k",
                                  "5", "--density-scale", "4", "--rays-per-point", std::to_string(rays_per_point), "--temporal", temporal,
                                  "--gaze-source", "provider", "--gaze-provider", "replay:" + gaze.string()};
    args.insert(args.end(), extra.begin(), extra.end());
    return run(name, args, frames);
  }
};

inline uint64_t total_rays(const nlohmann::json& counts) {
  return counts["primary"].get<uint64_t>() + counts["shadow"].get<uint64_t>() +
         counts["reflection"].get<uint64_t>() + counts["refraction"].get<uint64_t>();
}

// A run where every view was traced and reconstructed on the GPU, nothing fell back.
inline void expect_clean(const AppRun& r, const char* engine, int frames = kFrames, const char* temporal = "off") {
  ASSERT_EQ(r.process.exit_code, 0) << r.process.output;
  ASSERT_TRUE(r.stats.is_object()) << r.process.output;
  EXPECT_EQ(r.stats["engine"], engine);
  EXPECT_EQ(r.stats["frames_traced"], frames) << r.process.output;
  EXPECT_EQ(r.stats["views_fallback"], 0) << r.process.output;
  EXPECT_EQ(r.stats["callback_failures"], 0);
  EXPECT_EQ(r.stats["invalid_colours"], 0);
  EXPECT_EQ(r.stats["gpu_fallbacks"], 0);
  EXPECT_EQ(r.stats["fallback_flags"], 0) << "the scripted gaze must be used, not fixed foveation";
  EXPECT_EQ(r.stats["reconstruction"], "gpu");
  EXPECT_EQ(r.stats["temporal"], temporal) << "the temporal mode that ran";
}

}  // namespace foveart::layer::test
