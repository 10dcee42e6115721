// The simulated runtime against the OpenXR 1.0 specification's wording, through the real
// loader: the rules a conformance run found broken, one test each (time conversion on the
// virtual clock, action and action set errors, interaction profile bindings, path syntax,
// result names, form factors). Frame pacing across threads is pipelined_frames_test.cpp.
#include <gtest/gtest.h>

#include <cstring>
#include <string>

#include "interaction_profiles.h"
#include "xr_test_app.h"

namespace foveart::sim::test {
namespace {

class SpecConformance : public ::testing::Test {
 protected:
  void SetUp() override {
    clear_sim_env();
    set_env({{"FOVEART_SIM_CLOCK", "virtual"}});
  }
};

int64_t monotonic_now_ns() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

XrPath path(XrTestApp& app, const char* s) {
  XrPath p = XR_NULL_PATH;
  EXPECT_EQ(xrStringToPath(app.instance, s, &p), XR_SUCCESS) << s;
  return p;
}

XrActionSet make_action_set(XrTestApp& app, const char* name, XrResult* result) {
  auto info = xr<XrActionSetCreateInfo>(XR_TYPE_ACTION_SET_CREATE_INFO);
  std::snprintf(info.actionSetName, sizeof info.actionSetName, "%s", name);
  std::snprintf(info.localizedActionSetName, sizeof info.localizedActionSetName, "Set %s", name);
  XrActionSet set = XR_NULL_HANDLE;
  *result = xrCreateActionSet(app.instance, &info, &set);
  return set;
}

XrAction make_action(XrActionSet set, const char* name, XrActionType type, const std::vector<XrPath>& subaction_paths,
                     XrResult* result) {
  auto info = xr<XrActionCreateInfo>(XR_TYPE_ACTION_CREATE_INFO);
  std::snprintf(info.actionName, sizeof info.actionName, "%s", name);
  std::snprintf(info.localizedActionName, sizeof info.localizedActionName, "Action %s", name);
  info.actionType = type;
  info.countSubactionPaths = static_cast<uint32_t>(subaction_paths.size());
  info.subactionPaths = subaction_paths.empty() ? nullptr : subaction_paths.data();
  XrAction action = XR_NULL_HANDLE;
  *result = xrCreateAction(set, &info, &action);
  return action;
}

XrResult suggest(XrTestApp& app, const std::string& profile, XrAction action,
                 const std::vector<std::string>& bindings) {
  std::vector<XrActionSuggestedBinding> suggested;
  for (const auto& b : bindings) suggested.push_back({action, path(app, b.c_str())});
  auto info = xr<XrInteractionProfileSuggestedBinding>(XR_TYPE_INTERACTION_PROFILE_SUGGESTED_BINDING);
  info.interactionProfile = path(app, profile.c_str());
  info.countSuggestedBindings = static_cast<uint32_t>(suggested.size());
  info.suggestedBindings = suggested.data();
  return xrSuggestInteractionProfileBindings(app.instance, &info);
}

// XR_KHR_convert_timespec_time: under the virtual clock a predicted display time maps to
// CLOCK_MONOTONIC as it stood when xrWaitFrame returned, one frame period ahead, and back
// exactly.
TEST_F(SpecConformance, TimespecConversionAgreesWithTheVirtualClocksFrames) {
  XrTestApp app;
  ASSERT_EQ(app.create_instance(), XR_SUCCESS);
  ASSERT_EQ(app.create_session(), XR_SUCCESS);
  ASSERT_TRUE(app.run_until_state(XR_SESSION_STATE_FOCUSED));
  auto to_timespec = app.proc<PFN_xrConvertTimeToTimespecTimeKHR>("xrConvertTimeToTimespecTimeKHR");
  auto to_time = app.proc<PFN_xrConvertTimespecTimeToTimeKHR>("xrConvertTimespecTimeToTimeKHR");
  ASSERT_NE(to_timespec, nullptr);
  ASSERT_NE(to_time, nullptr);
  for (int frame = 0; frame < 5; ++frame) {
    const int64_t before_ns = monotonic_now_ns();
    auto state = xr<XrFrameState>(XR_TYPE_FRAME_STATE);
    ASSERT_EQ(app.empty_frame(&state), XR_SUCCESS);
    timespec ts{};
    ASSERT_EQ(to_timespec(app.instance, state.predictedDisplayTime, &ts), XR_SUCCESS);
    const int64_t after_ns = monotonic_now_ns();
    const int64_t display_ns = static_cast<int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
    // The wait returned between before_ns and after_ns; the display is one period later.
    EXPECT_GE(display_ns - state.predictedDisplayPeriod, before_ns) << "frame " << frame;
    EXPECT_LE(display_ns - state.predictedDisplayPeriod, after_ns) << "frame " << frame;
    XrTime back = 0;
    ASSERT_EQ(to_time(app.instance, &ts, &back), XR_SUCCESS);
    EXPECT_EQ(back, state.predictedDisplayTime) << "round trip, frame " << frame;
  }
}

TEST_F(SpecConformance, ActionAndActionSetErrorsAreTheSpecsCodes) {
  XrTestApp app;
  ASSERT_EQ(app.create_instance(), XR_SUCCESS);
  XrResult r = XR_SUCCESS;
  make_action_set(app, "", &r);
  EXPECT_EQ(r, XR_ERROR_NAME_INVALID) << "empty action set name";
  make_action_set(app, "Upper", &r);
  EXPECT_EQ(r, XR_ERROR_PATH_FORMAT_INVALID) << "malformed action set name";
  XrActionSet set = make_action_set(app, "set", &r);
  ASSERT_EQ(r, XR_SUCCESS);
  make_action(set, "", XR_ACTION_TYPE_BOOLEAN_INPUT, {}, &r);
  EXPECT_EQ(r, XR_ERROR_NAME_INVALID) << "empty action name";
  const XrPath left = path(app, "/user/hand/left");
  const XrPath right = path(app, "/user/hand/right");
  make_action(set, "twice", XR_ACTION_TYPE_BOOLEAN_INPUT, {left, right, left}, &r);
  EXPECT_EQ(r, XR_ERROR_PATH_UNSUPPORTED) << "a subaction path listed twice";
  make_action(set, "not_top_level", XR_ACTION_TYPE_BOOLEAN_INPUT, {path(app, "/user/hand")}, &r);
  EXPECT_EQ(r, XR_ERROR_PATH_UNSUPPORTED) << "/user/hand is no top-level path";
  XrAction buzz = make_action(set, "buzz", XR_ACTION_TYPE_VIBRATION_OUTPUT, {left, right}, &r);
  ASSERT_EQ(r, XR_SUCCESS);

  ASSERT_EQ(app.create_session(), XR_SUCCESS);
  auto name_info = xr<XrInputSourceLocalizedNameGetInfo>(XR_TYPE_INPUT_SOURCE_LOCALIZED_NAME_GET_INFO);
  name_info.sourcePath = path(app, "/user/hand/left/output/haptic");
  name_info.whichComponents = XR_INPUT_SOURCE_LOCALIZED_NAME_USER_PATH_BIT;
  uint32_t count = 0;
  EXPECT_EQ(xrGetInputSourceLocalizedName(app.session, &name_info, 0, &count, nullptr),
            XR_ERROR_ACTIONSET_NOT_ATTACHED);

  auto attach = xr<XrSessionActionSetsAttachInfo>(XR_TYPE_SESSION_ACTION_SETS_ATTACH_INFO);
  attach.countActionSets = 1;
  attach.actionSets = &set;
  ASSERT_EQ(xrAttachSessionActionSets(app.session, &attach), XR_SUCCESS);
  EXPECT_EQ(xrGetInputSourceLocalizedName(app.session, &name_info, 0, &count, nullptr), XR_SUCCESS);
  ASSERT_TRUE(app.run_until_state(XR_SESSION_STATE_FOCUSED));

  auto vibration = xr<XrHapticVibration>(XR_TYPE_HAPTIC_VIBRATION);
  vibration.duration = XR_MIN_HAPTIC_DURATION;
  vibration.amplitude = 0.5F;
  auto haptic = xr<XrHapticActionInfo>(XR_TYPE_HAPTIC_ACTION_INFO);
  haptic.action = buzz;
  const auto* feedback = reinterpret_cast<const XrHapticBaseHeader*>(&vibration);
  EXPECT_EQ(xrApplyHapticFeedback(app.session, &haptic, feedback), XR_SUCCESS);
  haptic.subactionPath = left;
  EXPECT_EQ(xrApplyHapticFeedback(app.session, &haptic, feedback), XR_SUCCESS);
  haptic.subactionPath = path(app, "/user/head");
  EXPECT_EQ(xrApplyHapticFeedback(app.session, &haptic, feedback), XR_ERROR_PATH_UNSUPPORTED)
      << "a path the action was not created with";
  haptic.subactionPath = static_cast<XrPath>(0x7FFF'FFFF);  // never handed out by xrStringToPath
  EXPECT_EQ(xrApplyHapticFeedback(app.session, &haptic, feedback), XR_ERROR_PATH_INVALID);
}

// xrSuggestInteractionProfileBindings accepts exactly the spec's binding paths per profile.
TEST_F(SpecConformance, SuggestedBindingsAreExactlyTheSpecsPathsPerProfile) {
  XrTestApp app;
  ASSERT_EQ(app.create_instance(), XR_SUCCESS);
  XrResult r = XR_SUCCESS;
  XrActionSet set = make_action_set(app, "bindings", &r);
  ASSERT_EQ(r, XR_SUCCESS);
  XrAction action = make_action(set, "any", XR_ACTION_TYPE_BOOLEAN_INPUT, {}, &r);
  ASSERT_EQ(r, XR_SUCCESS);

  // Every path of every profile, one call per profile (the eye gaze profile: its extension is on).
  for (const InteractionProfile& profile : interaction_profiles()) {
    std::vector<std::string> bindings(profile.binding_paths.begin(), profile.binding_paths.end());
    EXPECT_EQ(suggest(app, std::string(profile.path), action, bindings), XR_SUCCESS) << profile.path;
  }
  // Paths the spec lists on one profile only, or nowhere.
  EXPECT_EQ(suggest(app, "/interaction_profiles/htc/vive_pro", action, {"/user/head/input/system/click"}), XR_SUCCESS);
  EXPECT_EQ(suggest(app, "/interaction_profiles/htc/vive_pro", action, {"/user/hand/left/input/system/click"}),
            XR_ERROR_PATH_UNSUPPORTED);
  EXPECT_EQ(
      suggest(app, "/interaction_profiles/khr/simple_controller", action, {"/user/hand/left/input/trigger/value"}),
      XR_ERROR_PATH_UNSUPPORTED);
  EXPECT_EQ(suggest(app, "/interaction_profiles/oculus/touch_controller", action, {"/user/hand/right/input/x/click"}),
            XR_ERROR_PATH_UNSUPPORTED);
  EXPECT_EQ(suggest(app, "/interaction_profiles/oculus/touch_controller", action,
                    {"/user/hand/left/input/x/click", "/user/hand/left/input/trackpad/click"}),
            XR_ERROR_PATH_UNSUPPORTED)
      << "one bad path fails the whole call";
  EXPECT_EQ(
      suggest(app, "/interaction_profiles/acme/unknown_controller", action, {"/user/hand/left/input/select/click"}),
      XR_ERROR_PATH_UNSUPPORTED);
}

TEST_F(SpecConformance, EyeGazeProfileNeedsItsExtension) {
  XrTestApp app;
  ASSERT_EQ(app.create_instance(/*eye_gaze=*/false), XR_SUCCESS);
  XrResult r = XR_SUCCESS;
  XrActionSet set = make_action_set(app, "gaze", &r);
  ASSERT_EQ(r, XR_SUCCESS);
  XrAction pose = make_action(set, "pose", XR_ACTION_TYPE_POSE_INPUT, {}, &r);
  ASSERT_EQ(r, XR_SUCCESS);
  EXPECT_EQ(
      suggest(app, "/interaction_profiles/ext/eye_gaze_interaction", pose, {"/user/eyes_ext/input/gaze_ext/pose"}),
      XR_ERROR_PATH_UNSUPPORTED);
}

TEST_F(SpecConformance, PathsWithPeriodOnlyComponentsAreMalformed) {
  XrTestApp app;
  ASSERT_EQ(app.create_instance(), XR_SUCCESS);
  for (const char* bad : {"/.", "/..", "/...", "/../foo", "/foo/.", "/foo/..", "/foo/./bar", "/foo/../bar", "//foo",
                          "/foo/", "foo", "/Foo", ""}) {
    XrPath p = XR_NULL_PATH;
    EXPECT_EQ(xrStringToPath(app.instance, bad, &p), XR_ERROR_PATH_FORMAT_INVALID) << '"' << bad << '"';
  }
  for (const char* good : {"/.foo", "/foo.", "/foo/b.a.r", "/a/..b", "/user/hand/left"}) {
    XrPath p = XR_NULL_PATH;
    EXPECT_EQ(xrStringToPath(app.instance, good, &p), XR_SUCCESS) << '"' << good << '"';
  }
}

TEST_F(SpecConformance, UnknownResultsAreNamedWithTheirSignedValue) {
  XrTestApp app;
  ASSERT_EQ(app.create_instance(), XR_SUCCESS);
  char name[XR_MAX_RESULT_STRING_SIZE] = {};
  ASSERT_EQ(xrResultToString(app.instance, static_cast<XrResult>(-1000710001), name), XR_SUCCESS);
  EXPECT_STREQ(name, "XR_UNKNOWN_FAILURE_-1000710001");
  ASSERT_EQ(xrResultToString(app.instance, static_cast<XrResult>(1000710001), name), XR_SUCCESS);
  EXPECT_STREQ(name, "XR_UNKNOWN_SUCCESS_1000710001");
  ASSERT_EQ(xrResultToString(app.instance, XR_ERROR_PATH_UNSUPPORTED, name), XR_SUCCESS);
  EXPECT_STREQ(name, "XR_ERROR_PATH_UNSUPPORTED");
}

TEST_F(SpecConformance, FormFactorsNotOfferedAreUnsupported) {
  XrTestApp app;
  ASSERT_EQ(app.create_instance(), XR_SUCCESS);
  for (XrFormFactor form : {XR_FORM_FACTOR_HANDHELD_DISPLAY, XR_FORM_FACTOR_MAX_ENUM, static_cast<XrFormFactor>(0),
                            static_cast<XrFormFactor>(42)}) {
    auto info = xr<XrSystemGetInfo>(XR_TYPE_SYSTEM_GET_INFO);
    info.formFactor = form;
    XrSystemId system = XR_NULL_SYSTEM_ID;
    EXPECT_EQ(xrGetSystem(app.instance, &info, &system), XR_ERROR_FORM_FACTOR_UNSUPPORTED) << form;
  }
}

}  // namespace
}  // namespace foveart::sim::test
