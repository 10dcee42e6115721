// The layer's gaze from the gaze provider carries the provider's saccade flag
// to the frame (TAA restarts its history on it): a replayed trace with a 20 deg
// saccade between fixations must show FrameGaze::saccade while the eye is in
// flight, and not during the fixations; frames too slow to catch the ~40 ms flag
// must still see the saccade, in one frame.
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <thread>

#include <gtest/gtest.h>

#include "gaze_source.hpp"
#include "state.hpp"

namespace foveart::layer {
namespace {

int64_t steady_now_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

// 120 Hz: 0.4 s fixating straight ahead, a 20 deg rightward saccade over
// 4 samples (~600 deg/s), then 1.2 s fixating there.
std::filesystem::path write_saccade_trace(const std::filesystem::path& dir) {
  std::filesystem::create_directories(dir);
  const auto trace = dir / "saccade.csv";
  std::ofstream csv(trace);
  csv << "device_time_us,frame_id,valid,gaze_x,gaze_y,gaze_z\n";
  for (int i = 0; i < 192; ++i) {
    const double deg = i < 48 ? 0.0 : (i < 52 ? 5.0 * (i - 47) : 20.0);
    const double rad = deg * 3.14159265358979 / 180.0;
    csv << i * 8333 << "," << i << ",1," << std::sin(rad) << ",0," << std::cos(rad) << "\n";
  }
  return trace;
}

std::unique_ptr<GazeSource> replay_source(const std::filesystem::path& trace) {
  RendererSettings settings;
  settings.gaze_source = XR_FOVEATED_GAZE_SOURCE_PROVIDER_FOVEART;
  settings.gaze_provider_spec = "replay:" + trace.string();
  SessionState session;
  std::string warning;
  auto source = create_gaze_source(settings, session, &warning);
  EXPECT_TRUE(warning.empty()) << warning;
  return source;
}

TEST(ProviderGazeSource, CarriesTheSaccadeFlagToTheFrame) {
  const auto dir = std::filesystem::temp_directory_path() / ("foveart_gaze_source_" + std::to_string(::getpid()));
  const auto trace = write_saccade_trace(dir);
  auto source = replay_source(trace);
  ASSERT_NE(source, nullptr);

  // Ask at ~1 kHz, as frames would at display time, over the whole trace.
  bool saw_saccade = false, saccade_while_fixating = false, saw_valid = false;
  const auto start = std::chrono::steady_clock::now();
  while (std::chrono::steady_clock::now() - start < std::chrono::milliseconds(1500)) {
    GazeQuery q;
    q.now_ns = steady_now_ns();
    q.display_time = q.now_ns;
    const FrameGaze g = source->at(q);
    const double t_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (g.valid) saw_valid = true;
    if (g.saccade) {
      saw_saccade = true;
      // The first fixation ends at 0.4 s and the eye lands by 0.44 s: well inside
      // either fixation (allowing for the filters' lag) nothing may flag.
      if (t_s < 0.3 || t_s > 1.0) saccade_while_fixating = true;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  source.reset();
  std::filesystem::remove_all(dir);
  EXPECT_TRUE(saw_valid);
  EXPECT_TRUE(saw_saccade) << "the provider's in_saccade never reached the frame's gaze";
  EXPECT_FALSE(saccade_while_fixating);
}

TEST(ProviderGazeSource, FramesTooSlowForTheFlagStillSeeTheSaccadeOnce) {
  const auto dir = std::filesystem::temp_directory_path() / ("foveart_gaze_slow_" + std::to_string(::getpid()));
  const auto trace = write_saccade_trace(dir);
  auto source = replay_source(trace);
  ASSERT_NE(source, nullptr);

  // 5 frames a second at 0.1, 0.3, 0.5 ... s: the saccade (0.40-0.45 s) falls
  // between two of them; the flag itself lasts ~40 ms.
  int saccade_frames = 0, valid_frames = 0;
  double saccade_at_s = -1.0;
  const auto start = std::chrono::steady_clock::now();
  for (int frame = 0; frame < 7; ++frame) {
    std::this_thread::sleep_until(start + std::chrono::milliseconds(100 + 200 * frame));
    GazeQuery q;
    q.now_ns = steady_now_ns();
    q.display_time = q.now_ns;
    const FrameGaze g = source->at(q);
    valid_frames += g.valid ? 1 : 0;
    if (g.saccade) {
      ++saccade_frames;
      saccade_at_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
  }
  source.reset();
  std::filesystem::remove_all(dir);
  EXPECT_GE(valid_frames, 6);
  EXPECT_EQ(saccade_frames, 1) << "the saccade between two frames flags the next one, and only it";
  EXPECT_GT(saccade_at_s, 0.35) << "not before the saccade";
  EXPECT_LT(saccade_at_s, 1.0) << "the frame right after it (0.5 s, scheduler allowing)";
}

}  // namespace
}  // namespace foveart::layer
