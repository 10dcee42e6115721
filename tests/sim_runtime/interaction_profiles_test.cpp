// The interaction profile table against OpenXR 1.0 specification, section 6.4, and XR_EXT_eye_gaze_interaction.
#include "interaction_profiles.h"

#include <gtest/gtest.h>

#include <map>
#include <set>
#include <string>
#include <vector>

namespace foveart::sim::test {
namespace {

const InteractionProfile& profile(std::string_view path) {
  const InteractionProfile* p = find_interaction_profile(path);
  if (p == nullptr) {
    ADD_FAILURE() << "no profile " << path;
    static const InteractionProfile kEmpty{};
    return kEmpty;
  }
  return *p;
}

constexpr std::string_view kSimple = "/interaction_profiles/khr/simple_controller";
constexpr std::string_view kTouch = "/interaction_profiles/oculus/touch_controller";
constexpr std::string_view kVivePro = "/interaction_profiles/htc/vive_pro";
constexpr std::string_view kXbox = "/interaction_profiles/microsoft/xbox_controller";
constexpr std::string_view kEyeGaze = "/interaction_profiles/ext/eye_gaze_interaction";

TEST(InteractionProfiles, ListsTheNineCoreProfilesAndEyeGaze) {
  std::set<std::string> paths;
  for (const InteractionProfile& p : interaction_profiles()) paths.emplace(p.path);
  const std::set<std::string> expected = {
      "/interaction_profiles/khr/simple_controller",       "/interaction_profiles/google/daydream_controller",
      "/interaction_profiles/htc/vive_controller",         "/interaction_profiles/htc/vive_pro",
      "/interaction_profiles/microsoft/motion_controller", "/interaction_profiles/microsoft/xbox_controller",
      "/interaction_profiles/oculus/go_controller",        "/interaction_profiles/oculus/touch_controller",
      "/interaction_profiles/valve/index_controller",      "/interaction_profiles/ext/eye_gaze_interaction"};
  EXPECT_EQ(paths, expected);
  EXPECT_EQ(interaction_profiles().size(), expected.size());
}

TEST(InteractionProfiles, UnknownProfileNamesGiveNull) {
  EXPECT_EQ(find_interaction_profile(""), nullptr);
  EXPECT_EQ(find_interaction_profile("/interaction_profiles/fove/fove0"), nullptr);
  EXPECT_EQ(find_interaction_profile("/interaction_profiles/khr/simple_controller/"), nullptr);
  EXPECT_EQ(find_interaction_profile("/interaction_profiles/khr"), nullptr);
  EXPECT_EQ(find_interaction_profile("/interaction_profiles/ext/eye_gaze_interaction_ext"), nullptr);
}

TEST(InteractionProfiles, BindingCountsAreTheSpecsPerTopLevelPath) {
  // Per hand (or per the one top-level path) times the top-level paths, counted by hand from the spec's lists.
  const std::map<std::string, size_t> expected = {{"/interaction_profiles/khr/simple_controller", 5 * 2},
                                                  {"/interaction_profiles/google/daydream_controller", 7 * 2},
                                                  {"/interaction_profiles/htc/vive_controller", 12 * 2},
                                                  {"/interaction_profiles/htc/vive_pro", 4},
                                                  {"/interaction_profiles/microsoft/motion_controller", 13 * 2},
                                                  {"/interaction_profiles/microsoft/xbox_controller", 24},
                                                  {"/interaction_profiles/oculus/go_controller", 9 * 2},
                                                  {"/interaction_profiles/oculus/touch_controller", (5 + 11) * 2},
                                                  {"/interaction_profiles/valve/index_controller", 22 * 2},
                                                  {"/interaction_profiles/ext/eye_gaze_interaction", 1}};
  for (const auto& [path, count] : expected) EXPECT_EQ(profile(path).binding_paths.size(), count) << path;
}

TEST(InteractionProfiles, EachListIsNonEmptyUniqueAndUnderItsTopLevelPaths) {
  for (const InteractionProfile& p : interaction_profiles()) {
    ASSERT_FALSE(p.binding_paths.empty()) << p.path;
    ASSERT_FALSE(p.top_level_paths.empty()) << p.path;
    std::set<std::string_view> seen;
    for (std::string_view b : p.binding_paths) {
      EXPECT_TRUE(seen.insert(b).second) << p.path << " lists " << b << " twice";
      bool under_top = false;
      for (std::string_view top : p.top_level_paths) {
        if (b.starts_with(std::string(top) + "/input/") || b.starts_with(std::string(top) + "/output/")) {
          under_top = true;
        }
      }
      EXPECT_TRUE(under_top) << p.path << ": " << b;
      EXPECT_TRUE(is_supported_binding(p, b)) << p.path << ": " << b;
    }
  }
}

TEST(InteractionProfiles, SimpleControllerIsExactlyTheSpecsList) {
  const InteractionProfile& p = profile(kSimple);
  EXPECT_EQ(p.extension, "");
  EXPECT_EQ(p.top_level_paths, (std::vector<std::string_view>{"/user/hand/left", "/user/hand/right"}));
  const std::set<std::string_view> bindings(p.binding_paths.begin(), p.binding_paths.end());
  const std::set<std::string_view> expected = {
      "/user/hand/left/input/select/click", "/user/hand/left/input/menu/click", "/user/hand/left/input/grip/pose",
      "/user/hand/left/input/aim/pose",     "/user/hand/left/output/haptic",    "/user/hand/right/input/select/click",
      "/user/hand/right/input/menu/click",  "/user/hand/right/input/grip/pose", "/user/hand/right/input/aim/pose",
      "/user/hand/right/output/haptic"};
  EXPECT_EQ(bindings, expected);
  EXPECT_TRUE(is_supported_binding(p, "/user/hand/left/input/select/click"));
  EXPECT_TRUE(is_supported_binding(p, "/user/hand/right/output/haptic"));
  EXPECT_FALSE(is_supported_binding(p, "/user/hand/left/input/trigger/value"));
  EXPECT_FALSE(is_supported_binding(p, "/user/hand/left/input/select/value"));
  EXPECT_FALSE(is_supported_binding(p, "/user/head/input/select/click"));
  EXPECT_FALSE(is_supported_binding(p, "/user/gamepad/input/menu/click"));
}

TEST(InteractionProfiles, ViveProIsTheHeadOnly) {
  const InteractionProfile& p = profile(kVivePro);
  EXPECT_EQ(p.top_level_paths, (std::vector<std::string_view>{"/user/head"}));
  EXPECT_TRUE(is_supported_binding(p, "/user/head/input/system/click"));
  EXPECT_TRUE(is_supported_binding(p, "/user/head/input/volume_up/click"));
  EXPECT_TRUE(is_supported_binding(p, "/user/head/input/volume_down/click"));
  EXPECT_TRUE(is_supported_binding(p, "/user/head/input/mute_mic/click"));
  EXPECT_FALSE(is_supported_binding(p, "/user/hand/left/input/system/click"));
  EXPECT_FALSE(is_supported_binding(p, "/user/head/output/haptic"));
  EXPECT_FALSE(is_supported_binding(p, "/user/head/input/grip/pose"));
}

TEST(InteractionProfiles, TouchSplitsItsButtonsBetweenTheHands) {
  const InteractionProfile& p = profile(kTouch);
  for (const char* id : {"x/click", "x/touch", "y/click", "y/touch", "menu/click"}) {
    EXPECT_TRUE(is_supported_binding(p, std::string("/user/hand/left/input/") + id)) << id;
    EXPECT_FALSE(is_supported_binding(p, std::string("/user/hand/right/input/") + id)) << id;
  }
  for (const char* id : {"a/click", "a/touch", "b/click", "b/touch", "system/click"}) {
    EXPECT_TRUE(is_supported_binding(p, std::string("/user/hand/right/input/") + id)) << id;
    EXPECT_FALSE(is_supported_binding(p, std::string("/user/hand/left/input/") + id)) << id;
  }
  for (const char* hand : {"/user/hand/left", "/user/hand/right"}) {
    for (const char* sub :
         {"/input/squeeze/value", "/input/trigger/value", "/input/trigger/touch", "/input/thumbstick/x",
          "/input/thumbstick/y", "/input/thumbstick/click", "/input/thumbstick/touch", "/input/thumbrest/touch",
          "/input/grip/pose", "/input/aim/pose", "/output/haptic"}) {
      EXPECT_TRUE(is_supported_binding(p, std::string(hand) + sub)) << hand << sub;
    }
  }
}

TEST(InteractionProfiles, RejectsMadeUpComponentsAndOtherProfilesPaths) {
  const InteractionProfile& p = profile(kTouch);
  EXPECT_FALSE(is_supported_binding(p, "/user/hand/left/input/trigger/foo"));
  EXPECT_FALSE(is_supported_binding(p, "/user/hand/left/input/trigger/click"));  // Touch's trigger has no click
  EXPECT_FALSE(is_supported_binding(p, "/user/hand/left/input/squeeze/click"));
  EXPECT_FALSE(is_supported_binding(p, "/user/hand/left/input/trackpad/click"));
  EXPECT_FALSE(is_supported_binding(p, "/user/hand/left/input/trackpad"));
  EXPECT_FALSE(is_supported_binding(p, "/user/hand/left/input/select/click"));
  EXPECT_FALSE(is_supported_binding(p, "/user/hand/left/input/thumbstick/x/click"));
  EXPECT_FALSE(is_supported_binding(p, "/user/hand/left/input/trigger/value/"));
  EXPECT_FALSE(is_supported_binding(p, "/user/hand/left/output/haptic_left"));
  EXPECT_FALSE(is_supported_binding(p, "/user/hand/left/output/haptic/value"));
  EXPECT_FALSE(is_supported_binding(p, ""));
  EXPECT_FALSE(is_supported_binding(p, "/user/hand/left"));
  EXPECT_FALSE(is_supported_binding(p, "/user/hand/left/input"));
  EXPECT_FALSE(is_supported_binding(p, "/user/hand/left/output"));
  EXPECT_FALSE(is_supported_binding(p, "/user/head/input/trigger/value"));
  EXPECT_FALSE(
      is_supported_binding(profile("/interaction_profiles/htc/vive_controller"), "/user/hand/left/input/thumbstick/x"));
  EXPECT_FALSE(is_supported_binding(profile("/interaction_profiles/valve/index_controller"),
                                    "/user/hand/left/input/trackpad/click"));  // Index's trackpad has force, no click
}

TEST(InteractionProfiles, AcceptsAnIdentifierWithoutItsComponent) {
  // 6.3.2: /input/<identifier>[_<location>][/<component>], the runtime picking the component for a suggested binding.
  const InteractionProfile& touch = profile(kTouch);
  EXPECT_TRUE(is_supported_binding(touch, "/user/hand/left/input/trigger"));
  EXPECT_TRUE(is_supported_binding(touch, "/user/hand/right/input/thumbstick"));
  EXPECT_TRUE(is_supported_binding(touch, "/user/hand/left/input/squeeze"));
  EXPECT_TRUE(is_supported_binding(touch, "/user/hand/left/input/grip"));
  EXPECT_TRUE(is_supported_binding(touch, "/user/hand/left/input/x"));
  EXPECT_FALSE(is_supported_binding(touch, "/user/hand/right/input/x"));  // no x component on the right hand
  EXPECT_TRUE(is_supported_binding(touch, "/user/hand/right/input/system"));
  EXPECT_FALSE(is_supported_binding(touch, "/user/hand/left/input/system"));
  EXPECT_FALSE(is_supported_binding(touch, "/user/hand/left/input/trig"));

  const InteractionProfile& xbox = profile(kXbox);
  EXPECT_TRUE(is_supported_binding(xbox, "/user/gamepad/input/thumbstick_left"));
  EXPECT_TRUE(is_supported_binding(xbox, "/user/gamepad/input/trigger_right"));
  EXPECT_FALSE(is_supported_binding(xbox, "/user/gamepad/input/thumbstick"));
  EXPECT_FALSE(is_supported_binding(xbox, "/user/gamepad/input/trigger"));
  EXPECT_TRUE(is_supported_binding(xbox, "/user/gamepad/output/haptic_left_trigger"));
  EXPECT_FALSE(is_supported_binding(xbox, "/user/gamepad/output/haptic"));
  EXPECT_FALSE(is_supported_binding(xbox, "/user/gamepad/output"));

  EXPECT_TRUE(is_supported_binding(profile(kVivePro), "/user/head/input/system"));
}

TEST(InteractionProfiles, EyeGazeNeedsItsExtension) {
  const InteractionProfile& p = profile(kEyeGaze);
  EXPECT_EQ(p.extension, "XR_EXT_eye_gaze_interaction");
  EXPECT_EQ(p.top_level_paths, (std::vector<std::string_view>{"/user/eyes_ext"}));
  EXPECT_EQ(p.binding_paths, (std::vector<std::string_view>{"/user/eyes_ext/input/gaze_ext/pose"}));
  EXPECT_TRUE(is_supported_binding(p, "/user/eyes_ext/input/gaze_ext/pose"));
  EXPECT_TRUE(is_supported_binding(p, "/user/eyes_ext/input/gaze_ext"));
  EXPECT_FALSE(is_supported_binding(p, "/user/eyes_ext/input/gaze/pose"));
  EXPECT_FALSE(is_supported_binding(p, "/user/head/input/gaze_ext/pose"));
  EXPECT_FALSE(is_supported_binding(p, "/user/hand/left/input/aim/pose"));
  for (const InteractionProfile& core : interaction_profiles()) {
    if (core.path != kEyeGaze) {
      EXPECT_EQ(core.extension, "") << core.path;
    }
  }
}

}  // namespace
}  // namespace foveart::sim::test
