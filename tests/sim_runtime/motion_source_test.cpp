// The scripted motion as the runtime plays it (FOVEART_SIM_MOTION): the head in LOCAL,
// the eye tracker's 120 Hz samples in the traces' head space, looping, bad files.
#include "motion_source.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "sim_test_env.h"
#include "motion_math.hpp"

namespace foveart::sim {
namespace {

constexpr int64_t kGazePeriodNs = 8'333'333;  // 120 Hz, foveation::fove0()

using test::ns;
using test::angle_deg;

// Head yaw to the right, degrees: the forward (-z) axis turned about +y.
double yaw_deg(const glm::quat& q) {
  const glm::vec3 f = q * glm::vec3(0.0F, 0.0F, -1.0F);
  return static_cast<double>(glm::degrees(std::atan2(f.x, -f.z)));
}

TEST(MotionSource, BuiltinIsTheSeededFourSecondScript) {
  std::string error;
  const auto one = MotionSource::from_spec("builtin", 1, &error);
  ASSERT_TRUE(one.has_value()) << error;
  EXPECT_EQ(one->name(), "builtin (seed 1)");
  EXPECT_EQ(one->loop_period_ns(), 4'000'000'000);
  const auto seven = MotionSource::from_spec("builtin", 7, &error);
  ASSERT_TRUE(seven.has_value()) << error;
  // Another seed: other fixations, microsaccades and tracker noise.
  EXPECT_GT(angle_deg(one->gaze_at(ns(1.0)).direction, seven->gaze_at(ns(1.0)).direction), 1e-3);
}

TEST(MotionSource, HeadIsTheScriptsPoseLoweredToLocalAndLoops) {
  const motion::ScriptedMotion script = motion::builtin_motion(1);
  const MotionSource motion(script, "test");
  for (double t : {0.0, 0.25, 1.0, 2.5, 3.999}) {
    const motion::MotionSample s = script.at(t);
    const Pose head = motion.head_in_local(ns(t));
    EXPECT_NEAR(std::abs(glm::dot(head.orientation, s.head_orientation)), 1.0, 1e-6) << t;
    EXPECT_NEAR(head.position.x, s.head_position_m.x, 1e-6) << t;
    EXPECT_NEAR(head.position.y, s.head_position_m.y - kLocalAboveStageM, 1e-6) << t;
    EXPECT_NEAR(head.position.z, s.head_position_m.z, 1e-6) << t;
  }
  // The head turns: 20-30 deg/s over the first second.
  EXPECT_GT(yaw_deg(motion.head_in_local(ns(1.0)).orientation), 20.0);
  EXPECT_NEAR(std::abs(motion.head_in_local(0).position.y), 0.0, 1e-6) << "LOCAL is the start pose's height";
  // One loop later the same pose.
  const Pose a = motion.head_in_local(ns(0.5));
  const Pose b = motion.head_in_local(motion.loop_period_ns() + ns(0.5));
  EXPECT_NEAR(std::abs(glm::dot(a.orientation, b.orientation)), 1.0, 1e-6);
  EXPECT_NEAR(glm::distance(a.position, b.position), 0.0, 1e-6);
}

TEST(MotionSource, GazeIsSampledAt120HzWithForwardAlongPlusZAndInvalidInTheBlink) {
  const motion::ScriptedMotion script = motion::builtin_motion(1);
  const MotionSource motion(script, "test");
  // 1.003 s falls in sample 120, which holds until sample 121.
  const GazeSample s = motion.gaze_at(ns(1.003));
  EXPECT_EQ(s.offset_ns, 120 * kGazePeriodNs);
  EXPECT_TRUE(s.valid);
  const glm::vec3 g = script.at(static_cast<double>(120 * kGazePeriodNs) * 1e-9).gaze_head;
  EXPECT_LT(angle_deg(s.direction, glm::vec3(g.x, g.y, -g.z)), 1e-3) << "the script's -z forward becomes +z";
  EXPECT_GT(motion.gaze_at(0).direction.z, 0.99F);
  EXPECT_EQ(motion.gaze_at(121 * kGazePeriodNs - 1).offset_ns, 120 * kGazePeriodNs);
  EXPECT_EQ(motion.gaze_at(121 * kGazePeriodNs).offset_ns, 121 * kGazePeriodNs);
  // The 12 deg saccade at 1.5 s, the 150 ms blink at 3.0 s.
  EXPECT_GT(angle_deg(motion.gaze_at(ns(1.49)).direction, motion.gaze_at(ns(1.56)).direction), 10.0);
  EXPECT_TRUE(motion.gaze_at(ns(2.99)).valid);
  EXPECT_FALSE(motion.gaze_at(ns(3.01)).valid);
  EXPECT_FALSE(motion.gaze_at(ns(3.14)).valid);
  EXPECT_TRUE(motion.gaze_at(ns(3.16)).valid);
  // 480 samples per 4 s loop: the last (at 3.992 s) holds to the loop's end, then the grid restarts.
  EXPECT_EQ(motion.gaze_at(motion.loop_period_ns() - 1).offset_ns, 479 * kGazePeriodNs);
  EXPECT_EQ(motion.next_sample_ns(479 * kGazePeriodNs), motion.loop_period_ns());
  EXPECT_EQ(motion.next_sample_ns(motion.loop_period_ns()), motion.loop_period_ns() + kGazePeriodNs);
  const GazeSample looped = motion.gaze_at(motion.loop_period_ns() + ns(1.003));
  EXPECT_EQ(looped.offset_ns, motion.loop_period_ns() + 120 * kGazePeriodNs);
  EXPECT_LT(angle_deg(looped.direction, s.direction), 1e-4);
}

TEST(MotionSource, BadMotionFilesAreErrorsNamingFileLineAndColumn) {
  const std::string dir = test::fresh_dir("motion");
  const std::string path = dir + "/bad.csv";
  std::ofstream(path) << "time_s,qx,qy,qz,qw,px,py,pz,gx,gy,gz,valid\n"
                      << "0,0,0,0,1,0,1.6,0,0,0,-1,1\n"
                      << "0.01,0,0,0,abc,0,1.6,0,0,0,-1,1\n";
  std::string error;
  EXPECT_FALSE(MotionSource::from_spec(path, 1, &error).has_value());
  EXPECT_NE(error.find(path + ":3: column 5"), std::string::npos) << error;
  EXPECT_NE(error.find("'abc'"), std::string::npos) << error;
  error.clear();
  EXPECT_FALSE(MotionSource::from_spec(dir + "/missing.csv", 1, &error).has_value());
  EXPECT_NE(error.find(dir + "/missing.csv: no such file"), std::string::npos) << error;
  error.clear();
  EXPECT_FALSE(MotionSource::from_spec(dir, 1, &error).has_value());
  EXPECT_NE(error.find(dir + ": a directory, not a file"), std::string::npos) << error;
}

TEST(MotionSource, ReadsTheMotionCsvThatTheScriptWrites) {
  const std::string path = test::fresh_dir("motion") + "/builtin.csv";
  std::string error;
  ASSERT_TRUE(motion::save_motion_csv(motion::builtin_motion(3), path, &error)) << error;
  const auto from_file = MotionSource::from_spec(path, 1, &error);
  ASSERT_TRUE(from_file.has_value()) << error;
  EXPECT_EQ(from_file->name(), path);
  const MotionSource builtin(motion::builtin_motion(3), "builtin");
  EXPECT_EQ(from_file->loop_period_ns(), builtin.loop_period_ns());
  for (double t : {0.1, 1.52, 2.7}) {
    EXPECT_LT(angle_deg(from_file->gaze_at(ns(t)).direction, builtin.gaze_at(ns(t)).direction), 1e-3) << t;
    EXPECT_NEAR(std::abs(glm::dot(from_file->head_in_local(ns(t)).orientation,
                                  builtin.head_in_local(ns(t)).orientation)),
                1.0, 1e-6)
        << t;
  }
}

}  // namespace
}  // namespace foveart::sim
