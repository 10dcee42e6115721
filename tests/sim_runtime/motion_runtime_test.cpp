// FOVEART_SIM_MOTION through the real loader: the views and the eye gaze pose follow
// the scripted motion from xrBeginSession on (over FOVEART_SIM_HEAD and
// FOVEART_SIM_GAZE), and a motion that cannot be read fails xrCreateInstance.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/trigonometric.hpp>

#include "foveation/device.hpp"
#include <motion/scripted_motion.hpp>
#include "gaze_provider/gaze_math.h"
#include "gaze_provider/trace_csv.h"
#include "sim_runtime/sim_env.h"
#include "xr_test_app.h"
#include "motion_math.hpp"

namespace foveart::sim::test {
namespace {

// The virtual clock does not move before the first xrWaitFrame, so the session's
// xrBeginSession (the motion's origin) is at the virtual epoch.
constexpr XrTime kOrigin = env::kVirtualEpochNs;
constexpr int64_t kGazePeriodNs = 8'333'333;

XrTime at(double seconds) { return kOrigin + std::llround(seconds * 1e9); }

glm::quat to_glm(const XrQuaternionf& q) { return glm::quat(q.w, q.x, q.y, q.z); }
glm::vec3 to_glm(const XrVector3f& v) { return {v.x, v.y, v.z}; }

// Yaw to the right of the -z axis turned by q, degrees.
double yaw_deg(const glm::quat& q) {
  const glm::vec3 f = q * glm::vec3(0.0F, 0.0F, -1.0F);
  return static_cast<double>(glm::degrees(std::atan2(f.x, -f.z)));
}

using test::angle_deg;

XrSpace reference_space(XrSession session, XrReferenceSpaceType type) {
  auto info = xr<XrReferenceSpaceCreateInfo>(XR_TYPE_REFERENCE_SPACE_CREATE_INFO);
  info.referenceSpaceType = type;
  info.poseInReferenceSpace.orientation.w = 1.0F;
  XrSpace space = XR_NULL_HANDLE;
  EXPECT_EQ(xrCreateReferenceSpace(session, &info, &space), XR_SUCCESS);
  return space;
}

class SimRuntimeMotion : public ::testing::Test {
 protected:
  void SetUp() override { clear_sim_env(); }
};

TEST_F(SimRuntimeMotion, ViewsFollowTheScriptedHeadInsteadOfTheSway) {
  set_env({{"FOVEART_SIM_CLOCK", "virtual"}, {"FOVEART_SIM_MOTION", "builtin"}, {"FOVEART_SIM_HEAD", "sway"}});
  XrTestApp app;
  ASSERT_EQ(app.create_instance(), XR_SUCCESS);
  ASSERT_EQ(app.create_session(), XR_SUCCESS);
  ASSERT_TRUE(app.run_until_state(XR_SESSION_STATE_FOCUSED));
  const XrSpace local = reference_space(app.session, XR_REFERENCE_SPACE_TYPE_LOCAL);
  const XrSpace stage = reference_space(app.session, XR_REFERENCE_SPACE_TYPE_STAGE);
  const XrSpace view = reference_space(app.session, XR_REFERENCE_SPACE_TYPE_VIEW);
  const motion::ScriptedMotion script = motion::builtin_motion(1);

  for (double t_s : {0.0, 1.0, 2.25}) {
    const motion::MotionSample s = script.at(t_s);
    auto head = xr<XrSpaceLocation>(XR_TYPE_SPACE_LOCATION);
    ASSERT_EQ(xrLocateSpace(view, local, at(t_s), &head), XR_SUCCESS);
    ASSERT_NE(head.locationFlags & XR_SPACE_LOCATION_ORIENTATION_VALID_BIT, 0u);
    EXPECT_NEAR(yaw_deg(to_glm(head.pose.orientation)), yaw_deg(s.head_orientation), 0.01) << t_s << " s";
    EXPECT_NEAR(std::abs(glm::dot(to_glm(head.pose.orientation), s.head_orientation)), 1.0, 1e-6) << t_s;
    // LOCAL is 1.6 m above the script's floor, which is the STAGE.
    EXPECT_NEAR(head.pose.position.y, s.head_position_m.y - 1.6F, 1e-5) << t_s;
    auto head_in_stage = xr<XrSpaceLocation>(XR_TYPE_SPACE_LOCATION);
    ASSERT_EQ(xrLocateSpace(view, stage, at(t_s), &head_in_stage), XR_SUCCESS);
    EXPECT_NEAR(glm::distance(to_glm(head_in_stage.pose.position), s.head_position_m), 0.0, 1e-5) << t_s;
  }
  // After 1 s the head has turned 26 deg to the right (20-30 deg/s), far from the
  // sway's 5.9 deg: the motion wins over FOVEART_SIM_HEAD.
  auto head = xr<XrSpaceLocation>(XR_TYPE_SPACE_LOCATION);
  ASSERT_EQ(xrLocateSpace(view, local, at(1.0), &head), XR_SUCCESS);
  EXPECT_GT(yaw_deg(to_glm(head.pose.orientation)), 20.0);

  // The views: the head pose times the FOVE 0's eye offsets, same orientation.
  auto locate = xr<XrViewLocateInfo>(XR_TYPE_VIEW_LOCATE_INFO);
  locate.viewConfigurationType = XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO;
  locate.displayTime = at(1.0);
  locate.space = local;
  auto state = xr<XrViewState>(XR_TYPE_VIEW_STATE);
  std::vector<XrView> views(2, xr<XrView>(XR_TYPE_VIEW));
  uint32_t count = 0;
  ASSERT_EQ(xrLocateViews(app.session, &locate, &state, 2, &count, views.data()), XR_SUCCESS);
  const glm::quat q = to_glm(head.pose.orientation);
  for (uint32_t e = 0; e < 2; ++e) {
    const glm::vec3 offset(static_cast<float>(foveation::fove0().eye_offset_x_m(e)), 0.0F, 0.0F);
    const glm::vec3 expected = to_glm(head.pose.position) + q * offset;
    EXPECT_NEAR(glm::distance(to_glm(views[e].pose.position), expected), 0.0, 1e-6) << "eye " << e;
    EXPECT_NEAR(std::abs(glm::dot(to_glm(views[e].pose.orientation), q)), 1.0, 1e-6) << "eye " << e;
  }
  // The motion loops: 4 s later the same yaw.
  auto looped = xr<XrSpaceLocation>(XR_TYPE_SPACE_LOCATION);
  ASSERT_EQ(xrLocateSpace(view, local, at(5.0), &looped), XR_SUCCESS);
  EXPECT_NEAR(yaw_deg(to_glm(looped.pose.orientation)), yaw_deg(q), 0.01);
}

TEST_F(SimRuntimeMotion, EyeGazePoseIsTheScriptsGazeInTheTurningHeadInsteadOfTheTrace) {
  // A trace looking 30 deg left all the time: FOVEART_SIM_MOTION must win over it.
  const std::string trace = fresh_dir("gaze") + "/left.csv";
  {
    std::ofstream out(trace);
    gaze::TraceWriter writer(out);
    for (int i = 0; i < 10; ++i) {
      gaze::GazeSample s;
      s.device_time_ns = i * kGazePeriodNs;
      s.valid = true;
      s.combined_direction = gaze::from_yaw_pitch_deg(-30.0, 0.0);
      writer.write(s);
    }
  }
  set_env({{"FOVEART_SIM_CLOCK", "virtual"}, {"FOVEART_SIM_MOTION", "builtin"}, {"FOVEART_SIM_MOTION_SEED", "2"},
           {"FOVEART_SIM_GAZE", trace}});
  XrTestApp app;
  ASSERT_EQ(app.create_instance(), XR_SUCCESS);
  ASSERT_EQ(app.create_session(), XR_SUCCESS);
  GazeActions g = make_gaze_actions(app);
  const XrSpace local = reference_space(app.session, XR_REFERENCE_SPACE_TYPE_LOCAL);
  const XrSpace view = reference_space(app.session, XR_REFERENCE_SPACE_TYPE_VIEW);
  ASSERT_TRUE(app.run_until_state(XR_SESSION_STATE_FOCUSED));
  ASSERT_EQ(sync(app, g.set), XR_SUCCESS);
  const motion::ScriptedMotion script = motion::builtin_motion(2);

  for (double t_s : {0.5, 1.003, 1.52, 2.6}) {
    const int64_t sample_ns = (std::llround(t_s * 1e9) / kGazePeriodNs) * kGazePeriodNs;
    const glm::vec3 gaze_head = script.at(static_cast<double>(sample_ns) * 1e-9).gaze_head;  // -z forward
    auto sample_time = xr<XrEyeGazeSampleTimeEXT>(XR_TYPE_EYE_GAZE_SAMPLE_TIME_EXT);
    auto location = xr<XrSpaceLocation>(XR_TYPE_SPACE_LOCATION, &sample_time);
    ASSERT_EQ(xrLocateSpace(g.gaze_space, local, at(t_s), &location), XR_SUCCESS);
    ASSERT_NE(location.locationFlags & XR_SPACE_LOCATION_ORIENTATION_TRACKED_BIT, 0u) << t_s;
    EXPECT_EQ(sample_time.time, kOrigin + sample_ns) << t_s;
    auto head = xr<XrSpaceLocation>(XR_TYPE_SPACE_LOCATION);
    ASSERT_EQ(xrLocateSpace(view, local, at(t_s), &head), XR_SUCCESS);
    // The gaze ray (-z of the gaze pose) is the script's head-space gaze turned by the head.
    const glm::vec3 ray = to_glm(location.pose.orientation) * glm::vec3(0.0F, 0.0F, -1.0F);
    EXPECT_LT(angle_deg(ray, to_glm(head.pose.orientation) * gaze_head), 0.01) << t_s;
    EXPECT_NEAR(glm::distance(to_glm(location.pose.position), to_glm(head.pose.position)), 0.0, 1e-6);
  }
  // The 150 ms blink at 3.0 s: the eye tracker has no gaze.
  auto blink = xr<XrSpaceLocation>(XR_TYPE_SPACE_LOCATION);
  ASSERT_EQ(xrLocateSpace(g.gaze_space, local, at(3.07), &blink), XR_SUCCESS);
  EXPECT_EQ(blink.locationFlags, 0u);
  auto after = xr<XrSpaceLocation>(XR_TYPE_SPACE_LOCATION);
  ASSERT_EQ(xrLocateSpace(g.gaze_space, local, at(3.2), &after), XR_SUCCESS);
  EXPECT_NE(after.locationFlags & XR_SPACE_LOCATION_ORIENTATION_TRACKED_BIT, 0u);
}

TEST_F(SimRuntimeMotion, UnreadableMotionFailsInstanceCreationAndSaysWhere) {
  const std::string dir = fresh_dir("bad");
  const std::string bad = dir + "/motion.csv";
  std::ofstream(bad) << "time_s,qx,qy,qz,qw,px,py,pz,gx,gy,gz,valid\n0,0,0,0,1,0,1.6,0,0,0,-1,yes\n";
  for (const std::string& spec : {bad, dir + "/missing.csv"}) {
    clear_sim_env();
    set_env({{"FOVEART_SIM_MOTION", spec}});
    XrTestApp app;
    ::testing::internal::CaptureStderr();
    const XrResult r = app.create_instance();
    const std::string log = ::testing::internal::GetCapturedStderr();
    EXPECT_EQ(r, XR_ERROR_RUNTIME_FAILURE) << spec;
    EXPECT_NE(log.find("foveart-sim [error] FOVEART_SIM_MOTION: " + spec), std::string::npos) << log;
    if (spec == bad) {
      EXPECT_NE(log.find(bad + ":2: column 12 ('yes')"), std::string::npos) << log;
    }
  }
}

TEST_F(SimRuntimeMotion, MalformedSeedFailsInstanceCreationNamingTheVariable) {
  set_env({{"FOVEART_SIM_MOTION", "builtin"}, {"FOVEART_SIM_MOTION_SEED", "one"}});
  XrTestApp app;
  ::testing::internal::CaptureStderr();
  const XrResult r = app.create_instance();
  const std::string log = ::testing::internal::GetCapturedStderr();
  EXPECT_EQ(r, XR_ERROR_INITIALIZATION_FAILED);
  EXPECT_NE(log.find("FOVEART_SIM_MOTION_SEED='one' is not valid"), std::string::npos) << log;
}

}  // namespace
}  // namespace foveart::sim::test
