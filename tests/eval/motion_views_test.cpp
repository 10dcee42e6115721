// A scripted motion's frames as views and gaze pixels (eval/motion_views.hpp).
#include "gltf_fixtures.hpp"

#include <eval/motion_views.hpp>

#include <foveation/eye_rays.hpp>

#include <glm/gtc/quaternion.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

using namespace foveart;

namespace {

constexpr float kPi = 3.14159265f;

motion::MotionSample sample(double t, float head_yaw_deg, glm::vec3 gaze, bool valid = true, bool saccade = false) {
  motion::MotionSample s;
  s.time_s = t;
  s.head_orientation = glm::angleAxis(head_yaw_deg * kPi / 180.0f, glm::vec3(0, 1, 0));
  s.head_position_m = {0.0f, 1.6f, 0.0f};
  s.gaze_head = glm::normalize(gaze);
  s.gaze_valid = valid;
  s.saccade = saccade;
  return s;
}

// 100x80 px, 90 deg wide (tan 1), the eye 32 mm right of a head at (1, 2, 3).
FoveartEyeView eye_at_rest(const foveation::EyePose& head) {
  foveation::EyePose eye = head;
  eye.position_m += head.orientation * glm::vec3(0.032f, 0.0f, 0.0f);
  return foveation::make_eye_view(1, 100, 80, eye, -kPi / 4, kPi / 4, std::atan(0.8f), -std::atan(0.8f));
}

}  // namespace

TEST(MotionViews, HeadSitsAtTheScenesHeadWhereTheMotionStandsInLocal) {
  foveation::EyePose scene_head{glm::vec3(1, 2, 3), glm::angleAxis(kPi / 2, glm::vec3(0, 1, 0))};
  motion::MotionSample s = sample(0.0, 0.0f, {0, 0, -1});
  s.head_position_m = {0.1f, 1.6f, 0.0f};
  const foveation::EyePose h = eval::head_in_scene(scene_head, s);
  // 0.1 m to the motion's right is -z in a scene head turned 90 deg to the left.
  EXPECT_NEAR(h.position_m.x, 1.0f, 1e-6f);
  EXPECT_NEAR(h.position_m.y, 2.0f, 1e-6f);
  EXPECT_NEAR(h.position_m.z, 2.9f, 1e-6f);
  EXPECT_NEAR(std::abs(glm::dot(h.orientation, scene_head.orientation)), 1.0f, 1e-6f);
}

TEST(MotionViews, FramesFollowTheHeadKeepTheEyeOffsetAndProjectTheGaze) {
  const float tan10 = std::tan(10.0f * kPi / 180.0f);
  const motion::ScriptedMotion motion({sample(0.0, 0.0f, {0, 0, -1}),
                                          sample(1.0, 90.0f, {tan10, 0, -1}),
                                          sample(2.0, 90.0f, {0, 0, -1}, false, false),
                                          sample(3.0, 90.0f, {0, 0, -1}, true, true)});
  const foveation::EyePose head{glm::vec3(1, 2, 3), glm::quat(1, 0, 0, 0)};
  eval::MotionWindow w;
  w.start_s = 0.0;
  w.fps = 1.0;
  w.frames = 4;
  std::string error;
  ASSERT_TRUE(eval::check_motion_window(motion, w, &error)) << error;
  const auto frames = eval::motion_frames(motion, w, eye_at_rest(head), head);
  ASSERT_EQ(frames.size(), 4u);
  EXPECT_DOUBLE_EQ(frames[1].time_s, 1.0);
  // Frame 0: at rest, gaze ahead: the lens centre.
  EXPECT_NEAR(frames[0].view.position_m[0], 1.032f, 1e-6f);
  EXPECT_EQ(frames[0].gaze_px, glm::vec2(50, 40));
  // Frame 1: the head turned 90 deg left (about +y): the eye's 32 mm to the right now point to -z.
  EXPECT_NEAR(frames[1].view.position_m[0], 1.0f, 1e-6f);
  EXPECT_NEAR(frames[1].view.position_m[2], 3.0f - 0.032f, 1e-6f);
  // Gaze 10 deg right of the eye's axis: x = 50 + tan(10 deg) * 50 = 58.8 -> 59.
  EXPECT_EQ(frames[1].gaze_px, glm::vec2(59, 40));
  EXPECT_FALSE(frames[1].blink);
  // Frame 2: a blink keeps the last valid gaze pixel.
  EXPECT_TRUE(frames[2].blink);
  EXPECT_EQ(frames[2].gaze_px, glm::vec2(59, 40));
  // Frame 3: the saccade flag comes through; the gaze is back at the centre.
  EXPECT_TRUE(frames[3].saccade);
  EXPECT_EQ(frames[3].gaze_px, glm::vec2(50, 40));
  // The view keeps the frustum and size of the eye at rest.
  EXPECT_EQ(frames[3].view.width_px, 100u);
  EXPECT_FLOAT_EQ(frames[3].view.angle_left_rad, -kPi / 4);
}

TEST(MotionViews, GazeOffTheViewFallsBackToTheLensCentre) {
  const motion::ScriptedMotion motion({sample(0.0, 0.0f, {1, 0, 0}), sample(1.0, 0.0f, {1, 0, 0})});
  const foveation::EyePose head{};
  eval::MotionWindow w;
  w.fps = 1.0;
  w.frames = 2;
  const auto frames = eval::motion_frames(motion, w, eye_at_rest(head), head);
  EXPECT_TRUE(frames[0].gaze_off_view);
  EXPECT_EQ(frames[0].gaze_px, glm::vec2(50, 40));
}

TEST(MotionViews, WindowOutsideTheMotionIsNamed) {
  const motion::ScriptedMotion motion({sample(0.0, 0.0f, {0, 0, -1}), sample(1.0, 0.0f, {0, 0, -1})});
  eval::MotionWindow w;
  w.frames = 71;  // 70 fps from 0: the 71st frame is at 1 s, the last sample
  std::string error;
  EXPECT_TRUE(eval::check_motion_window(motion, w, &error)) << error;
  // The message of the window's first problem (empty when it has none).
  const auto problem = [&] {
    std::string e;
    return eval::check_motion_window(motion, w, &e) ? std::string() : e;
  };
  w.frames = 72;
  EXPECT_NE(problem().find("past the motion's end"), std::string::npos);
  w.frames = 1;
  EXPECT_NE(problem().find("--frames"), std::string::npos);
  w.frames = 2;
  w.start_s = -0.5;
  EXPECT_NE(problem().find("--start-s"), std::string::npos);
  w.start_s = 0.0;
  w.fps = 0.0;
  EXPECT_NE(problem().find("--fps"), std::string::npos);
}

TEST(MotionViews, LoadsTheBuiltinAndNamesABadFile) {
  std::string error;
  const auto builtin = eval::load_motion("builtin", &error);
  ASSERT_TRUE(builtin.has_value()) << error;
  EXPECT_NEAR(builtin->duration_s(), 4.0, 1e-9);
  engine_test::TempDir dir;
  const auto file = dir.path / "bad.csv";
  std::ofstream(file) << "time_s,qx,qy,qz,qw,px,py,pz,gx,gy,gz,valid\n0,0,0,0,1,0,1.6,0,0,0,-1,1\n0.1,0,0,0,1,0,1.6,x,0,0,-1,1\n";
  EXPECT_FALSE(eval::load_motion(file.string(), &error).has_value());
  EXPECT_NE(error.find("bad.csv:3: column 8"), std::string::npos) << error;
  EXPECT_FALSE(eval::load_motion((dir.path / "missing.csv").string(), &error).has_value());
  EXPECT_NE(error.find("missing.csv"), std::string::npos) << error;
}
