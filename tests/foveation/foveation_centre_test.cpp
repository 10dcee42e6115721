// The foveation centre through the built-in motion's gaze at FOVE resolution
// (70 Hz frames): without a deadband the point set moves in most frames of a
// fixation (tracker noise and microsaccades cross whole pixels); with the
// default 1 deg deadband it moves a few times per fixation at most, never
// lags the gaze by more than the deadband, and follows a saccade in its first frame.
#include <cmath>
#include <cstdio>
#include <numbers>

#include <gtest/gtest.h>

#include "foveation/display_model.hpp"
#include "foveation/foveated_view.hpp"
#include "foveation/foveation_centre.hpp"
#include <motion/scripted_motion.hpp>

namespace foveart::foveation {
namespace {

using motion::builtin_motion;
using motion::MotionSample;
using motion::ScriptedMotion;

struct Playback {
  int moves = 0;             // frames whose centre differs from the last frame's
  double max_lag_px = 0.0;   // largest |centre - gaze|
  int saccade_frames = 0;
  int saccade_frames_at_gaze = 0;
};

Playback play(const ScriptedMotion& motion, const DisplayModel& display, double deadband_deg) {
  const double px_per_rad = display.view_distance_px;
  FoveationCentre centre(deadband_deg * px_per_rad * std::numbers::pi / 180.0);
  Playback p;
  glm::vec2 last{-1.0f, -1.0f};
  for (int frame = 0; frame / 70.0 < motion.duration_s(); ++frame) {
    const MotionSample s = motion.at(frame / 70.0);
    // The layer's pixel: the gaze through a pinhole at the view centre, rounded.
    const double tx = double(s.gaze_head.x) / -double(s.gaze_head.z), ty = double(s.gaze_head.y) / -double(s.gaze_head.z);
    const glm::vec2 gaze = glm::round(glm::vec2(float(display.width_px / 2 + px_per_rad * tx),
                                                float(display.height_px / 2 - px_per_rad * ty)));
    const glm::vec2 c = centre.update(gaze, s.saccade || !s.gaze_valid);
    p.moves += frame > 0 && c != last ? 1 : 0;
    p.max_lag_px = std::max(p.max_lag_px, double(glm::distance(c, gaze)));
    if (s.saccade) {
      ++p.saccade_frames;
      p.saccade_frames_at_gaze += c == gaze ? 1 : 0;
    }
    last = c;
  }
  return p;
}

TEST(FoveationCentre, SteadyThroughFixationsAndAtOnceOnASaccade) {
  const DisplayModel fove = *display_preset("fove");
  const ScriptedMotion motion = builtin_motion(1);
  const ViewSettings defaults;
  const Playback follow = play(motion, fove, 0.0);
  const Playback held = play(motion, fove, defaults.centre_deadband_deg);
  const double deadband_px = defaults.centre_deadband_deg * fove.view_distance_px * std::numbers::pi / 180.0;
  std::printf("built-in motion, %d frames at 70 Hz: the centre moved in %d frames without a deadband, %d with %.1f deg "
              "(%.1f px); largest lag %.1f px\n",
              int(motion.duration_s() * 70.0), follow.moves, held.moves, defaults.centre_deadband_deg, deadband_px,
              held.max_lag_px);
  EXPECT_GT(follow.moves, 150) << "noise and microsaccades cross whole pixels in most frames";
  EXPECT_LT(held.moves * 8, follow.moves);
  EXPECT_LE(held.max_lag_px, deadband_px);
  ASSERT_GT(held.saccade_frames, 0);
  EXPECT_EQ(held.saccade_frames_at_gaze, held.saccade_frames) << "a saccade is followed in its own frame";
}

}  // namespace
}  // namespace foveart::foveation
