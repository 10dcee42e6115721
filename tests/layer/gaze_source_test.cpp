// The layer's gaze from the gaze provider carries the provider's saccade flag
// to the frame (TAA restarts its history on it): a replayed trace with a 20 deg
// saccade between fixations must show FrameGaze::saccade while the eye is in
// flight, and not during the fixations; frames too slow to catch the ~40 ms flag
// must still see the saccade, in one frame. The provider runs on a virtual clock
// (tests/common/manual_clock.hpp) and the frames ask at its times: exact, on any
// machine.
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <memory>
#include <unistd.h>

#include <gtest/gtest.h>

#include "gaze_source.hpp"
#include "manual_clock.hpp"
#include "state.hpp"

namespace foveart::layer {
namespace {

using foveart::test::ManualClock;

constexpr int64_t kMs = 1'000'000;

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

std::unique_ptr<GazeSource> replay_source(const std::filesystem::path& trace, std::shared_ptr<ManualClock> clock) {
  RendererSettings settings;
  settings.gaze_source = XR_FOVEATED_GAZE_SOURCE_PROVIDER_FOVEART;
  settings.gaze_provider_spec = "replay:" + trace.string();
  SessionState session;
  std::string warning;
  auto source = create_gaze_source(settings, session, &warning, std::move(clock));
  EXPECT_TRUE(warning.empty()) << warning;
  return source;
}

// A frame's question at virtual time t: composition and display now.
FrameGaze ask(GazeSource& source, int64_t t_ns) {
  GazeQuery q;
  q.now_ns = t_ns;
  q.display_time = t_ns;
  return source.at(q);
}

TEST(ProviderGazeSource, CarriesTheSaccadeFlagToTheFrame) {
  const auto dir = std::filesystem::temp_directory_path() / ("foveart_gaze_source_" + std::to_string(::getpid()));
  const auto trace = write_saccade_trace(dir);
  auto clock = std::make_shared<ManualClock>();
  const int64_t start = clock->now_ns();  // the replay starts here
  auto source = replay_source(trace, clock);
  ASSERT_NE(source, nullptr);
  foveart::test::ReleaseAtExit release{*clock};  // before the source stops its provider

  // Ask every millisecond, as frames would at display time, over the whole trace.
  bool saw_saccade = false, saccade_while_fixating = false, saw_valid = false;
  for (int64_t t_ms = 0; t_ms < 1500; ++t_ms) {
    ASSERT_TRUE(clock->run_until(start + t_ms * kMs)) << "at " << t_ms << " ms";
    const FrameGaze g = ask(*source, clock->now_ns());
    if (g.valid) saw_valid = true;
    if (g.saccade) {
      saw_saccade = true;
      // The first fixation ends at 0.4 s and the eye lands by 0.44 s: well inside
      // either fixation (allowing for the filters' lag) nothing may flag.
      if (t_ms < 300 || t_ms > 1000) saccade_while_fixating = true;
    }
  }
  clock->release();
  source.reset();
  std::filesystem::remove_all(dir);
  EXPECT_TRUE(saw_valid);
  EXPECT_TRUE(saw_saccade) << "the provider's in_saccade never reached the frame's gaze";
  EXPECT_FALSE(saccade_while_fixating);
}

TEST(ProviderGazeSource, FramesTooSlowForTheFlagStillSeeTheSaccadeOnce) {
  const auto dir = std::filesystem::temp_directory_path() / ("foveart_gaze_slow_" + std::to_string(::getpid()));
  const auto trace = write_saccade_trace(dir);
  auto clock = std::make_shared<ManualClock>();
  const int64_t start = clock->now_ns();
  auto source = replay_source(trace, clock);
  ASSERT_NE(source, nullptr);
  foveart::test::ReleaseAtExit release{*clock};  // before the source stops its provider

  // 5 frames a second at 0.1, 0.3, 0.5 ... s: the saccade (0.40-0.45 s) falls
  // between two of them; the flag itself lasts ~40 ms.
  int saccade_frames = 0, valid_frames = 0, saccade_frame = -1;
  for (int frame = 0; frame < 7; ++frame) {
    ASSERT_TRUE(clock->run_until(start + (100 + 200 * frame) * kMs)) << "frame " << frame;
    const FrameGaze g = ask(*source, clock->now_ns());
    valid_frames += g.valid ? 1 : 0;
    if (g.saccade) {
      ++saccade_frames;
      saccade_frame = frame;
    }
  }
  clock->release();
  source.reset();
  std::filesystem::remove_all(dir);
  EXPECT_EQ(valid_frames, 7);
  EXPECT_EQ(saccade_frames, 1) << "the saccade between two frames flags the next one, and only it";
  EXPECT_EQ(saccade_frame, 2) << "the frame at 0.5 s, right after the saccade (0.40-0.45 s)";
}

}  // namespace
}  // namespace foveart::layer
