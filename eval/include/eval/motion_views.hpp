// The frames of a scripted head and gaze motion (motion/scripted_motion.hpp)
// as `fovea-eval motion` and the price list's temporal columns render them:
// frame i at time start + i / fps; the eye's view is the head pose times the
// eye's offset; the gaze pixel is the motion's gaze projected through the eye's
// frustum and rounded, as the layer does (layer/src/foveated_renderer.cpp
// render_eye). Pure math, no I/O but the motion's loading.
//
// Where the motion sits in the scene: as hello_foveated on the simulated
// runtime places it. The motion's world is the stage (the built-in head is
// 1.6 m above its floor); the runtime's LOCAL space is a standing head above
// it (motion::head_pose_above_standing_eye); the app puts LOCAL at the
// scene's head pose (its camera, or one that frames it). So the head in the
// scene is scene_head * (q(t), p(t) - (0, 1.6, 0)).
#pragma once

#include <foveation/eye_rays.hpp>
#include <foveation/ray_trace.h>
#include <motion/scripted_motion.hpp>

#include <glm/vec2.hpp>

#include <optional>
#include <string>
#include <vector>

namespace foveart::eval {

struct MotionWindow {
  double start_s = 0.0;
  double fps = 70.0;  // the FOVE 0's display rate
  int frames = 3;
};

struct MotionFrame {
  int index = 0;
  double time_s = 0.0;
  FoveartEyeView view{};
  glm::vec2 gaze_px{};         // whole pixels
  bool saccade = false;        // the motion's sample lies inside a saccade
  bool blink = false;          // the gaze is not valid: gaze_px keeps the last valid one (the lens centre before any)
  bool gaze_off_view = false;  // the gaze points 87 deg or more off the view axis: the lens centre, as the layer
};

// "builtin" (motion::builtin_motion(1)) or a CSV file (motion::load_motion_csv);
// nullopt with *error naming the file, line and column on bad input.
std::optional<motion::ScriptedMotion> load_motion(const std::string& spec, std::string* error);

// False and *error saying what is wrong with the window for this motion (start
// beyond it, frames running past its end, a bad rate). Needs at least 2 frames.
[[nodiscard]] bool check_motion_window(const motion::ScriptedMotion& motion, const MotionWindow& window,
                                       std::string* error);

// The head pose in the scene at one sample of the motion.
foveation::EyePose head_in_scene(const foveation::EyePose& scene_head, const motion::MotionSample& sample);

// The window's frames. `eye_at_rest` is the eye's view with the head at
// `scene_head` (size, frustum and the eye's offset from the head, which every
// frame keeps); the window must have passed check_motion_window.
std::vector<MotionFrame> motion_frames(const motion::ScriptedMotion& motion, const MotionWindow& window,
                                       const FoveartEyeView& eye_at_rest, const foveation::EyePose& scene_head);

}  // namespace foveart::eval
