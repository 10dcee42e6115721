// A scripted head and gaze motion: head orientation and position plus the
// gaze direction in head space over time, the same for the simulated runtime
// (FOVEART_SIM_MOTION) and for the lab (`fovea-eval motion`, the price list's
// temporal columns), so a motion measured offline is the motion played through
// the layer. Its own library (foveart::motion), owned by neither: it needs GLM
// and the eye model (foveation/eye_rays.hpp) only.
//
// Head space: +x right, +y up, -z forward (OpenXR view convention); the gaze
// is a unit direction in it. Pure math; the CSV reader is the only I/O.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <glm/gtc/quaternion.hpp>
#include <glm/vec3.hpp>

#include "foveation/eye_rays.hpp"

namespace foveart::motion {

// A script's world is the floor frame (the OpenXR STAGE space); a standing
// head is this high. Players of a script (the simulated runtime's LOCAL space,
// `fovea-eval motion`) put their origin here so a head at rest sits at 0.
inline constexpr float kStandingEyeHeightM = 1.6f;

struct MotionSample {
  double time_s = 0.0;
  glm::quat head_orientation{1.0f, 0.0f, 0.0f, 0.0f};  // head space -> world
  glm::vec3 head_position_m{0.0f, kStandingEyeHeightM, 0.0f};
  glm::vec3 gaze_head{0.0f, 0.0f, -1.0f};  // unit, head space
  bool gaze_valid = true;                  // false during a blink
  bool saccade = false;                    // ground truth: this sample lies inside a saccade
};

// A sample's head pose with its origin moved up to a standing head: the pose
// in a player's space whose origin is kStandingEyeHeightM above the script's
// floor (the simulated runtime's LOCAL space, `fovea-eval motion`'s scene head).
inline foveation::EyePose head_pose_above_standing_eye(const MotionSample& s) {
  return foveation::EyePose{s.head_position_m - glm::vec3(0.0f, kStandingEyeHeightM, 0.0f), glm::normalize(s.head_orientation)};
}

class ScriptedMotion {
 public:
  ScriptedMotion() = default;
  // Samples in increasing time (throws std::invalid_argument otherwise, or when empty).
  explicit ScriptedMotion(std::vector<MotionSample> samples);

  // The motion at time t (clamped to the script): head slerped and lerped,
  // gaze normalised-lerped between the neighbouring samples; validity and the
  // saccade flag from the earlier one.
  MotionSample at(double time_s) const;
  double duration_s() const { return samples_.empty() ? 0.0 : samples_.back().time_s; }
  const std::vector<MotionSample>& samples() const { return samples_; }

 private:
  std::vector<MotionSample> samples_;
};

// The built-in motion, 4 s at 1 kHz: head yaw at 20 deg/s (10-30 deg/s over
// the script: 20 + 10 sin) with physiological tremor (0.15 deg at 9 Hz in yaw,
// 0.1 deg at 11 Hz in pitch, 0.5 mm of translation); gaze in fixations of
// 0.4-0.6 s, each with microsaccades (0.15-0.4 deg, ~25 ms) and drift
// (0.5 deg/s), tracker noise (0.05 deg rms), one 12 deg saccade at 1.5 s
// (~45 ms) and one 150 ms blink at 3.0 s. Deterministic for a seed.
ScriptedMotion builtin_motion(std::uint64_t seed = 1);

// CSV with header "time_s,qx,qy,qz,qw,px,py,pz,gx,gy,gz,valid[,saccade]";
// nullopt and *error naming the file, line and column on bad input.
std::optional<ScriptedMotion> load_motion_csv(const std::filesystem::path& path, std::string* error);
// False and *error naming the file when it cannot be written.
[[nodiscard]] bool save_motion_csv(const ScriptedMotion& motion, const std::filesystem::path& path, std::string* error);

}  // namespace foveart::motion
