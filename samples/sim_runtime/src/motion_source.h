// The scripted head and gaze motion (motion/scripted_motion.hpp, foveart::motion) as the simulated
// headset plays it (FOVEART_SIM_MOTION): the head pose of VIEW in LOCAL and the eye
// tracker's samples, both from one script on one time base, looping.
//
// Frames: the script's world is the STAGE (floor at y = 0; the built-in motion's head
// is 1.6 m above it), so the head in LOCAL is the script's pose lowered by
// kLocalAboveStageM. Gaze leaves here in the head space of gaze traces (+x right,
// +y up, +z forward: the script's -z forward with z flipped), like GazeSource.
//
// Time: offset_ns counts from the motion's origin (the session's xrBeginSession) and
// maps to script time first + (offset mod period), period = last - first sample time.
// The eye tracker samples the script on the headset's 120 Hz grid, restarted at each
// loop: round(period / 8.333 ms) samples per loop (480 for the built-in 4 s), the last
// held to the loop's end. A sample is invalid where the script's gaze is (a blink).
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include <motion/scripted_motion.hpp>

#include "gaze_source.h"
#include "pose_math.h"

namespace foveart::sim {

// LOCAL sits this far above the STAGE floor (the motion's world frame).
inline constexpr float kLocalAboveStageM = motion::kStandingEyeHeightM;

class MotionSource {
 public:
  explicit MotionSource(motion::ScriptedMotion motion, std::string name);

  // "builtin": motion::builtin_motion(seed); anything else is a CSV path
  // (motion::load_motion_csv; the seed is unused). nullopt and a message naming
  // the file, line and column on bad input.
  static std::optional<MotionSource> from_spec(const std::string& spec, uint64_t seed,
                                               std::string* error);

  // Head (VIEW) pose in LOCAL at offset_ns (< 0 counts as 0).
  Pose head_in_local(int64_t offset_ns) const;
  // The newest eye-tracker sample at or before offset_ns; its offset_ns is the
  // sample's time on the same time base.
  GazeSample gaze_at(int64_t offset_ns) const;
  // The time of the sample after the one at sample_offset_ns (a gaze_at().offset_ns).
  int64_t next_sample_ns(int64_t sample_offset_ns) const;

  int64_t loop_period_ns() const { return period_ns_; }
  const motion::ScriptedMotion& motion() const { return *motion_; }
  const std::string& name() const { return name_; }  // "builtin (seed 1)" or the path

 private:
  // Script time of an offset inside its loop, and where that loop starts.
  double script_time_s(int64_t in_loop_ns) const;
  void split(int64_t offset_ns, int64_t& loop_start_ns, int64_t& in_loop_ns) const;

  std::shared_ptr<const motion::ScriptedMotion> motion_;
  std::string name_;
  int64_t period_ns_ = 0;         // 0: a single sample, no looping
  int64_t samples_per_loop_ = 1;  // eye-tracker samples in one loop
};

}  // namespace foveart::sim
