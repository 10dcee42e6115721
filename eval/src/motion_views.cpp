// A scripted motion's frames as eye views and gaze pixels (motion_views.hpp).
#include <eval/motion_views.hpp>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <cmath>
#include <sstream>
#include <utility>

namespace foveart::eval {

std::optional<motion::ScriptedMotion> load_motion(const std::string& spec, std::string* error) {
  if (spec == "builtin") return motion::builtin_motion(1);
  if (spec.empty()) {
    *error = "--motion: expected 'builtin' or a CSV file";
    return std::nullopt;
  }
  std::optional<motion::ScriptedMotion> motion = motion::load_motion_csv(spec, error);
  if (!motion) *error = "--motion: " + *error;
  return motion;
}

namespace {

std::string motion_window_problem(const motion::ScriptedMotion& motion, const MotionWindow& w) {
  std::ostringstream s;
  if (!std::isfinite(w.fps) || w.fps < 1.0 || w.fps > 1000.0) return "--fps must be in 1..1000";
  if (w.frames < 2) return "--frames must be at least 2 with --motion (flicker needs pairs of frames)";
  const double first = motion.samples().front().time_s, last = motion.duration_s();
  if (!std::isfinite(w.start_s) || w.start_s < first || w.start_s > last) {
    s << "--start-s must be inside the motion (" << first << " to " << last << " s), got " << w.start_s;
    return s.str();
  }
  const double end_s = w.start_s + double(w.frames - 1) / w.fps;
  if (end_s > last + 1e-9) {
    s << w.frames << " frames at " << w.fps << " fps from " << w.start_s << " s end at " << end_s
      << " s, past the motion's end at " << last << " s";
    return s.str();
  }
  return "";
}

}  // namespace

bool check_motion_window(const motion::ScriptedMotion& motion, const MotionWindow& w, std::string* error) {
  std::string problem = motion_window_problem(motion, w);
  if (problem.empty()) return true;
  *error = std::move(problem);
  return false;
}

foveation::EyePose head_in_scene(const foveation::EyePose& scene_head, const motion::MotionSample& sample) {
  const foveation::EyePose in_local = motion::head_pose_above_standing_eye(sample);
  foveation::EyePose head;
  head.orientation = glm::normalize(scene_head.orientation * in_local.orientation);
  head.position_m = scene_head.position_m + scene_head.orientation * in_local.position_m;
  return head;
}

std::vector<MotionFrame> motion_frames(const motion::ScriptedMotion& motion, const MotionWindow& w,
                                       const FoveartEyeView& eye_at_rest, const foveation::EyePose& scene_head) {
  // The eye's offset from the head, in head space (the display's IPD, as render_view placed it).
  const foveation::EyePose rest = foveation::eye_pose(eye_at_rest);
  const glm::vec3 eye_offset_head = glm::conjugate(scene_head.orientation) * (rest.position_m - scene_head.position_m);
  const foveation::EyeFrustum frustum = foveation::eye_frustum(eye_at_rest);
  const glm::vec2 lens_centre = foveation::lens_centre_px(frustum);
  glm::vec2 last_valid = lens_centre;
  std::vector<MotionFrame> frames;
  frames.reserve(std::size_t(w.frames));
  for (int i = 0; i < w.frames; ++i) {
    MotionFrame f;
    f.index = i;
    f.time_s = w.start_s + double(i) / w.fps;
    const motion::MotionSample s = motion.at(f.time_s);
    foveation::EyePose eye = head_in_scene(scene_head, s);
    eye.position_m += eye.orientation * eye_offset_head;
    f.view = eye_at_rest;
    f.view.position_m[0] = eye.position_m.x;
    f.view.position_m[1] = eye.position_m.y;
    f.view.position_m[2] = eye.position_m.z;
    f.view.orientation_xyzw[0] = eye.orientation.x;
    f.view.orientation_xyzw[1] = eye.orientation.y;
    f.view.orientation_xyzw[2] = eye.orientation.z;
    f.view.orientation_xyzw[3] = eye.orientation.w;
    f.saccade = s.saccade;
    f.blink = !s.gaze_valid;
    if (f.blink) {
      f.gaze_px = last_valid;
    } else {
      // The eye looks along the head's axes (no vergence): the gaze in eye view space is the head-space gaze.
      f.gaze_off_view = !foveation::gaze_pixel(frustum, s.gaze_head, &f.gaze_px);
      if (f.gaze_off_view) f.gaze_px = lens_centre;
      last_valid = f.gaze_px;
    }
    frames.push_back(f);
  }
  return frames;
}

}  // namespace foveart::eval
