// The scripted head and gaze motion played through the real loader, the layer and
// the simulated FOVE runtime on lavapipe: the runtime turns the head every frame
// (FOVEART_SIM_MOTION=builtin) while the gaze provider replays the same motion's gaze
// (sim-motion-trace's export) through its own saccade detector and blink hold. The
// TAA history must restart in the first frame the provider flagged for each saccade
// or blink, and only there, on the CPU and on the GPU reconstruction path alike,
// with the image history ("temporal": "image") and the render cache ("rays") on either path.
//
// Clock: virtual. The runtime's clock moves one 70 Hz period per frame
// (FOVEART_SIM_CLOCK=virtual) and the layer steps the provider's clock to each frame's
// display time ("gaze_clock": "display_time"), so head and gaze share one time base and
// each frame sees every gaze sample due by its display time, however loaded the
// machine: nothing here depends on real time. A frame reports a saccade or blink that
// began since the frame before (gaze::OnsetLatch), as the provider's saccade flag itself
// lasts only about 40 ms (5 samples at 120 Hz). The eyes are small (80x90) to keep the
// sanitizer builds quick.
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "app_output.hpp"
#include "child_process.hpp"
#include "motion_source.h"
#include "motion_trace.h"
#include "test_env.hpp"

namespace foveart::layer::test {
namespace {

using foveart::test::ProcessResult;
using foveart::test::run_process;

constexpr int kTimeoutS = 900;
// 240 frames span 3.43 s at 70 Hz: the script's saccade at 1.5 s and its
// 150 ms blink at 3.0 s.
constexpr int kFrames = 240;
// The built-in script is 4 s long and loops: at each loop's end the head jumps
// back 80 deg and the gaze 12 deg. History continuity is judged in every loop,
// away from its seam (display times count from the first traced frame, a frame
// or two after the motion's origin at xrBeginSession).
constexpr double kLoopS = 4.0;
constexpr double kSeamMarginS = 0.1;

bool near_a_loop_seam(double t_s) {
  const double phase_s = std::fmod(t_s, kLoopS);
  return phase_s > kLoopS - kSeamMarginS || (t_s > kLoopS - kSeamMarginS && phase_s < kSeamMarginS);
}

struct AppRun {
  ProcessResult process;
  nlohmann::json stats;
};

class LayerMotion : public ::testing::TestWithParam<const char*> {
 protected:
  void SetUp() override {
    ASSERT_TRUE(have_runtime()) << "the simulated runtime's manifest is missing";
    env_ = std::make_unique<IsolatedEnv>();
    for (const char* name : {"FOVEART_SIM_CAPTURE_DIR", "FOVEART_SIM_CAPTURE_EVERY", "FOVEART_SIM_EYE_TRACKING",
                             "FOVEART_SIM_GAZE", "FOVEART_SIM_HEAD", "FOVEART_SIM_MOTION",
                             "FOVEART_SIM_MOTION_SEED"}) {
      ::unsetenv(name);
    }
  }

  AppRun launch(std::vector<std::string> args, const char* log_name) {
    args.insert(args.begin(), {FOVEART_HELLO_FOVEATED, "--json", "--eye-size", "80", "90"});
    AppRun r;
    r.process = run_process(args, env_->root() / log_name, kTimeoutS);
    r.stats = trailing_json(r.process.output);
    return r;
  }

  std::unique_ptr<IsolatedEnv> env_;
};

TEST_P(LayerMotion, TemporalHistoryRestartsAtTheOnsetOfEachSaccadeAndBlink) {
  const std::string path = GetParam();
  const bool ray_cache = path.rfind("ray_cache_", 0) == 0;
  const std::string reconstruction = ray_cache ? path.substr(10) : path;  // "ray_cache_gpu": on the GPU
  // The tables for 80x90 first, into the suite's cache: a first frame that builds them
  // would block while the replay runs on, past the saccade.
  configure_hello_foveated(*env_, 2, reconstruction.c_str(), ray_cache ? "rays" : "image",
                           R"("gaze_clock": "display_time")");
  ::unsetenv("FOVEART_SIM_CAPTURE_DIR");
  const AppRun warm = launch({"--gaze-source", "none"}, "warm.log");
  ASSERT_EQ(warm.process.exit_code, 0) << warm.process.output;

  // The motion's gaze as the provider's trace, long enough never to end during the run.
  std::string error;
  const auto motion = sim::MotionSource::from_spec("builtin", 1, &error);
  ASSERT_TRUE(motion.has_value()) << error;
  const auto trace = env_->root() / "motion_gaze.csv";
  ASSERT_TRUE(sim::write_motion_gaze_trace_file(*motion, 120.0, trace.string(), &error)) << error;
  IsolatedEnv::set("FOVEART_SIM_MOTION", "builtin");
  IsolatedEnv::set("FOVEART_SIM_MOTION_SEED", "1");
  IsolatedEnv::set("FOVEART_SIM_CLOCK", "virtual");
  IsolatedEnv::set("FOVEART_SIM_FRAMES", std::to_string(kFrames).c_str());
  const AppRun r = launch({"--gaze-source", "provider", "--gaze-provider", "replay:" + trace.string()}, "motion.log");
  ASSERT_EQ(r.process.exit_code, 0) << r.process.output;
  ASSERT_TRUE(r.stats.is_object()) << r.process.output;
  EXPECT_EQ(r.stats["reconstruction"], reconstruction);
  EXPECT_EQ(r.stats["temporal"], ray_cache ? "rays" : "image");
  EXPECT_EQ(r.stats["gaze_source"], "provider");
  EXPECT_EQ(r.stats["views_fallback"], 0);
  EXPECT_EQ(r.stats["gaze_lost_frames"], 0) << "the stepped clock lets the replay deliver every sample due";
  ASSERT_EQ(r.stats["frames_traced"], kFrames);

  const auto& reset = r.stats["temporal_reset_per_frame"];
  const auto& saccade = r.stats["gaze_saccade_per_frame"];
  const auto& blink = r.stats["gaze_blink_per_frame"];
  const auto& time_s = r.stats["display_time_s_per_frame"];
  ASSERT_EQ(reset.size(), static_cast<std::size_t>(kFrames));
  ASSERT_EQ(saccade.size(), reset.size());
  ASSERT_EQ(blink.size(), reset.size());
  ASSERT_EQ(time_s.size(), reset.size());

  // The first frame has no history yet.
  EXPECT_TRUE(reset[0][0].get<bool>() && reset[0][1].get<bool>());
  int saccade_frames = 0, blink_frames = 0, continuous_frames = 0, onsets = 0;
  uint64_t restarts = 0;
  for (std::size_t f = 0; f < reset.size(); ++f) {
    const bool left = reset[f][0].get<bool>(), right = reset[f][1].get<bool>();
    restarts += (left ? 1u : 0u) + (right ? 1u : 0u);
    const bool flagged = saccade[f].get<bool>() || blink[f].get<bool>();
    saccade_frames += saccade[f].get<bool>() ? 1 : 0;
    blink_frames += blink[f].get<bool>() ? 1 : 0;
    const double t_s = time_s[f].get<double>();
    const bool flagged_before = f > 0 && (saccade[f - 1].get<bool>() || blink[f - 1].get<bool>());
    if (flagged && !flagged_before) {
      // (a) The frame after detection: both eyes start over in the first flagged frame itself.
      EXPECT_TRUE(left && right) << "frame " << f << " at " << t_s << " s: the provider flagged a "
                                 << (saccade[f].get<bool>() ? "saccade" : "blink")
                                 << " but the history did not restart (left " << left << ", right " << right << ")";
      ++onsets;
    } else if (flagged) {
      // (a') Later frames of the same saccade or blink accumulate again (the gaze moves
      // ~10 px of these 80 px eyes in a 12 deg saccade: below the 40 px jump rule).
      EXPECT_FALSE(left || right) << "frame " << f << " at " << t_s
                                  << " s: the history restarted again inside one saccade or blink";
    } else if (f > 0 && !near_a_loop_seam(t_s)) {
      // (c) The head turns every frame (10-30 deg/s plus tremor): the history follows it.
      EXPECT_FALSE(left || right) << "frame " << f << " at " << t_s
                                  << " s: history restarted without a saccade or blink (left " << left
                                  << ", right " << right << ")";
      ++continuous_frames;
    }
  }
  // (b) The provider saw the motion's saccade and blink.
  EXPECT_GT(saccade_frames, 0);
  EXPECT_GT(blink_frames, 0);
  EXPECT_GE(onsets, 2) << "the saccade's and the blink's first frames";
  std::cout << "[ measured ] " << continuous_frames << " of " << kFrames << " frames judged for continuity over "
            << time_s.back().get<double>() << " s, " << onsets << " saccade or blink onsets\n";
  // Flags and seams take a few frames a loop: most frames are judged.
  EXPECT_GE(continuous_frames, kFrames / 2) << "too few frames away from the flags and the loop seams to judge";
  EXPECT_EQ(r.stats["temporal_resets"].get<uint64_t>(), restarts) << "the per-frame flags add up to the renderer's count";
}

INSTANTIATE_TEST_SUITE_P(Paths, LayerMotion, ::testing::Values("cpu", "gpu", "ray_cache_cpu", "ray_cache_gpu"),
                         [](const ::testing::TestParamInfo<const char*>& path) { return std::string(path.param); });

}  // namespace
}  // namespace foveart::layer::test
