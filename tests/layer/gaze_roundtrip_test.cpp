// A gaze recording, replayed by the simulated runtime, foveates where it looked:
// a trace written by the gaze provider's writer (what `gaze-diag stream --record`
// writes; head space, +z forward) looking 15 deg left and 10 deg up ->
// FOVEART_SIM_GAZE -> the runtime's XR_EXT_eye_gaze_interaction -> the layer with
// gaze source eye_gaze_interaction -> XrFoveatedRendererStatsFOVEART::gazePixel per
// eye, as hello_foveated --json reports it ("gaze_px_per_frame").
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <numbers>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "app_output.hpp"
#include "child_process.hpp"
#include "gaze_provider/gaze_math.h"
#include "gaze_provider/trace_csv.h"
#include "test_env.hpp"

namespace foveart::layer::test {
namespace {

constexpr int kTimeoutS = 900;
constexpr int kFrames = 3;
constexpr double kYawDeg = -15.0;   // left
constexpr double kPitchDeg = 10.0;  // up

// Two seconds of a steady fixation at 120 Hz, longer than the frames the app runs.
void write_fixation_trace(const fs::path& path, const gaze::Vec3f& direction) {
  std::ofstream out(path);
  gaze::TraceWriter writer(out);
  for (int i = 0; i < 240; ++i) {
    gaze::GazeSample s;
    s.device_time_ns = 3'000'000'000 + i * 8'333'333LL;
    s.host_time_ns = s.device_time_ns;
    s.frame_id = static_cast<std::uint64_t>(i);
    s.valid = true;
    s.eye_state = gaze::EyeState::open;
    s.confidence = 1.0F;
    s.combined_direction = direction;
    s.left = {{-0.032F, 0.0F, 0.0F}, direction, true, gaze::EyeState::open};
    s.right = {{0.032F, 0.0F, 0.0F}, direction, true, gaze::EyeState::open};
    writer.write(s);
  }
  ASSERT_TRUE(writer.ok());
}

// The runtime variables this test sets, cleared again for the tests after it.
struct SimGazeVariables {
  ~SimGazeVariables() {
    for (const char* name : {"FOVEART_SIM_GAZE", "FOVEART_SIM_CAPTURE_EVERY"}) ::unsetenv(name);
  }
};

TEST(GazeRoundTrip, RecordedGazeFoveatesWhereTheRecordingLooked) {
  FOVEART_REQUIRE_RUNTIME();
  IsolatedEnv env;
  const SimGazeVariables restore;
  configure_hello_foveated(env, kFrames);
  ::unsetenv("FOVEART_SIM_EYE_TRACKING");
  IsolatedEnv::set("FOVEART_SIM_CAPTURE_EVERY", "1000");  // frames.csv, one PNG pair
  const gaze::Vec3f looked = gaze::from_yaw_pitch_deg(kYawDeg, kPitchDeg);
  const fs::path trace = env.root() / "recorded.csv";
  write_fixation_trace(trace, looked);
  IsolatedEnv::set("FOVEART_SIM_GAZE", trace);

  const auto run = foveart::test::run_process({FOVEART_HELLO_FOVEATED, "--json", "--eye-size", "320", "360",
                                               "--gaze-source", "eye_gaze_interaction", "--temporal", "off"},
                                              env.root() / "hello_foveated.log", kTimeoutS);
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const auto stats = trailing_json(run.output);
  ASSERT_TRUE(stats.is_object()) << run.output;
  EXPECT_EQ(stats["gaze_source"], "eye_gaze_interaction");
  EXPECT_EQ(stats["gaze_lost_frames"], 0) << "every frame must use the recorded gaze";
  ASSERT_EQ(stats["views"].size(), 2u);
  ASSERT_EQ(stats["gaze_px_per_frame"].size(), std::size_t(kFrames));

  for (int e = 0; e < 2; ++e) {
    const auto& view = stats["views"][e];
    const double width_px = view["size_px"][0].get<double>(), height_px = view["size_px"][1].get<double>();
    const double tan_left = std::tan(view["fov_rad"][0].get<double>());
    const double tan_right = std::tan(view["fov_rad"][1].get<double>());
    const double tan_up = std::tan(view["fov_rad"][2].get<double>());
    const double tan_down = std::tan(view["fov_rad"][3].get<double>());
    // Pinhole projection of the recorded direction (the head is still and the eyes'
    // views are parallel to it, so both eyes see the fixation at infinity alike).
    const double tan_x = double(looked.x) / double(looked.z), tan_y = double(looked.y) / double(looked.z);
    const double expected_x = width_px * (tan_x - tan_left) / (tan_right - tan_left);
    const double expected_y = height_px * (tan_up - tan_y) / (tan_up - tan_down);
    // Tolerance: the layer rounds the gaze pixel (0.5 px), plus 0.25 deg of gaze at this
    // view's centre pixels per degree (W/2 / tan(right) px per radian; about 0.64 px
    // for 320 px over the FOVE 0's 95 deg). A sign error lands tens of pixels away.
    const double px_per_deg = 0.5 * width_px / tan_right * std::numbers::pi / 180.0;
    const double tolerance_px = 0.5 + 0.25 * px_per_deg;
    for (const auto& row : stats["gaze_px_per_frame"]) {
      const double x = row[1 + 2 * e].get<double>(), y = row[2 + 2 * e].get<double>();
      EXPECT_LT(x, 0.5 * width_px) << "eye " << e << ": a gaze to the left foveates the left half";
      EXPECT_LT(y, 0.5 * height_px) << "eye " << e << ": a gaze upwards foveates the upper half";
      EXPECT_NEAR(x, expected_x, tolerance_px) << "eye " << e << " frame " << row[0];
      EXPECT_NEAR(y, expected_y, tolerance_px) << "eye " << e << " frame " << row[0];
    }
  }
}

}  // namespace
}  // namespace foveart::layer::test
