// The table of OpenXR 1.0 specification, section 6.4 (1.0.x text), and the XR_EXT_eye_gaze_interaction profile.
#include "interaction_profiles.h"

#include <deque>
#include <string>

namespace foveart::sim {
namespace {

constexpr std::string_view kLeft = "/user/hand/left";
constexpr std::string_view kRight = "/user/hand/right";
constexpr std::string_view kEveryPath = "";

// Subpaths the spec lists on one top-level path only (`only`), or on every one of the profile's (kEveryPath).
struct SubpathGroup {
  std::string_view only;
  std::vector<std::string_view> subpaths;
};

struct ProfileSpec {
  std::string_view path;
  std::string_view extension;
  std::vector<std::string_view> top_level_paths;
  std::vector<SubpathGroup> groups;
};

// One function per profile, transcribed from the spec. Paths marked "may not be available for application use"
// (system/...) are still in the spec's allowlist, so they are listed. Extensions that add paths to these profiles
// are not covered.
ProfileSpec khr_simple_controller() {
  return {"/interaction_profiles/khr/simple_controller",
          "",
          {kLeft, kRight},
          {{kEveryPath,
            {"/input/select/click", "/input/menu/click", "/input/grip/pose", "/input/aim/pose", "/output/haptic"}}}};
}

ProfileSpec google_daydream_controller() {
  return {"/interaction_profiles/google/daydream_controller",
          "",
          {kLeft, kRight},
          {{kEveryPath,
            {"/input/select/click", "/input/trackpad/x", "/input/trackpad/y", "/input/trackpad/click",
             "/input/trackpad/touch", "/input/grip/pose", "/input/aim/pose"}}}};
}

ProfileSpec htc_vive_controller() {
  return {"/interaction_profiles/htc/vive_controller",
          "",
          {kLeft, kRight},
          {{kEveryPath,
            {"/input/system/click", "/input/squeeze/click", "/input/menu/click", "/input/trigger/click",
             "/input/trigger/value", "/input/trackpad/x", "/input/trackpad/y", "/input/trackpad/click",
             "/input/trackpad/touch", "/input/grip/pose", "/input/aim/pose", "/output/haptic"}}}};
}

ProfileSpec htc_vive_pro() {
  return {"/interaction_profiles/htc/vive_pro",
          "",
          {"/user/head"},
          {{kEveryPath,
            {"/input/system/click", "/input/volume_up/click", "/input/volume_down/click", "/input/mute_mic/click"}}}};
}

ProfileSpec microsoft_motion_controller() {
  return {
      "/interaction_profiles/microsoft/motion_controller",
      "",
      {kLeft, kRight},
      {{kEveryPath,
        {"/input/menu/click", "/input/squeeze/click", "/input/trigger/value", "/input/thumbstick/x",
         "/input/thumbstick/y", "/input/thumbstick/click", "/input/trackpad/x", "/input/trackpad/y",
         "/input/trackpad/click", "/input/trackpad/touch", "/input/grip/pose", "/input/aim/pose", "/output/haptic"}}}};
}

ProfileSpec microsoft_xbox_controller() {
  return {"/interaction_profiles/microsoft/xbox_controller",
          "",
          {"/user/gamepad"},
          {{kEveryPath,
            {"/input/menu/click",
             "/input/view/click",
             "/input/a/click",
             "/input/b/click",
             "/input/x/click",
             "/input/y/click",
             "/input/dpad_down/click",
             "/input/dpad_right/click",
             "/input/dpad_up/click",
             "/input/dpad_left/click",
             "/input/shoulder_left/click",
             "/input/shoulder_right/click",
             "/input/thumbstick_left/click",
             "/input/thumbstick_right/click",
             "/input/trigger_left/value",
             "/input/trigger_right/value",
             "/input/thumbstick_left/x",
             "/input/thumbstick_left/y",
             "/input/thumbstick_right/x",
             "/input/thumbstick_right/y",
             "/output/haptic_left",
             "/output/haptic_right",
             "/output/haptic_left_trigger",
             "/output/haptic_right_trigger"}}}};
}

ProfileSpec oculus_go_controller() {
  return {
      "/interaction_profiles/oculus/go_controller",
      "",
      {kLeft, kRight},
      {{kEveryPath,
        {"/input/system/click", "/input/trigger/click", "/input/back/click", "/input/trackpad/x", "/input/trackpad/y",
         "/input/trackpad/click", "/input/trackpad/touch", "/input/grip/pose", "/input/aim/pose"}}}};
}

ProfileSpec oculus_touch_controller() {
  return {"/interaction_profiles/oculus/touch_controller",
          "",
          {kLeft, kRight},
          {{kLeft, {"/input/x/click", "/input/x/touch", "/input/y/click", "/input/y/touch", "/input/menu/click"}},
           {kRight, {"/input/a/click", "/input/a/touch", "/input/b/click", "/input/b/touch", "/input/system/click"}},
           {kEveryPath,
            {"/input/squeeze/value", "/input/trigger/value", "/input/trigger/touch", "/input/thumbstick/x",
             "/input/thumbstick/y", "/input/thumbstick/click", "/input/thumbstick/touch", "/input/thumbrest/touch",
             "/input/grip/pose", "/input/aim/pose", "/output/haptic"}}}};
}

ProfileSpec valve_index_controller() {
  return {"/interaction_profiles/valve/index_controller",
          "",
          {kLeft, kRight},
          {{kEveryPath,
            {"/input/system/click",  "/input/system/touch",     "/input/a/click",          "/input/a/touch",
             "/input/b/click",       "/input/b/touch",          "/input/squeeze/value",    "/input/squeeze/force",
             "/input/trigger/click", "/input/trigger/value",    "/input/trigger/touch",    "/input/thumbstick/x",
             "/input/thumbstick/y",  "/input/thumbstick/click", "/input/thumbstick/touch", "/input/trackpad/x",
             "/input/trackpad/y",    "/input/trackpad/force",   "/input/trackpad/touch",   "/input/grip/pose",
             "/input/aim/pose",      "/output/haptic"}}}};
}

// XR_EXT_eye_gaze_interaction, "Eye gaze input".
ProfileSpec ext_eye_gaze_interaction() {
  return {"/interaction_profiles/ext/eye_gaze_interaction",
          "XR_EXT_eye_gaze_interaction",
          {"/user/eyes_ext"},
          {{kEveryPath, {"/input/gaze_ext/pose"}}}};
}

// In the spec's order.
std::vector<ProfileSpec> profile_specs() {
  return {
      khr_simple_controller(),       google_daydream_controller(), htc_vive_controller(),  htc_vive_pro(),
      microsoft_motion_controller(), microsoft_xbox_controller(),  oculus_go_controller(), oculus_touch_controller(),
      valve_index_controller(),      ext_eye_gaze_interaction()};
}

// The profiles with their full paths, built once; `storage` owns the strings the views point at (a deque never
// moves its elements on push_back).
struct Table {
  std::deque<std::string> storage;
  std::vector<InteractionProfile> profiles;

  Table() {
    for (const ProfileSpec& spec : profile_specs()) {
      InteractionProfile& profile = profiles.emplace_back();
      profile.path = spec.path;
      profile.extension = spec.extension;
      profile.top_level_paths = spec.top_level_paths;
      for (std::string_view top : spec.top_level_paths) {
        for (const SubpathGroup& group : spec.groups) {
          if (!group.only.empty() && group.only != top) continue;
          for (std::string_view subpath : group.subpaths) {
            profile.binding_paths.emplace_back(storage.emplace_back(std::string(top) + std::string(subpath)));
          }
        }
      }
    }
  }
};

const Table& table() {
  static const Table t;
  return t;
}

// Whether `binding` is `full` with its component omitted: `full` is <top>/input/<identifier>[_<location>]/<component>
// and `binding` is <top>/input/<identifier>[_<location>].
bool is_identifier_of(std::string_view full, std::string_view binding) {
  const size_t slash = full.rfind('/');
  if (slash == std::string_view::npos || full.substr(0, slash) != binding) return false;
  return binding.substr(0, binding.rfind('/')).ends_with("/input");
}

}  // namespace

const std::vector<InteractionProfile>& interaction_profiles() {
  return table().profiles;
}

const InteractionProfile* find_interaction_profile(std::string_view path) {
  for (const InteractionProfile& profile : table().profiles) {
    if (profile.path == path) return &profile;
  }
  return nullptr;
}

// Omitted components, 6.3.2 "Input subpaths": an input subpath is /input/<identifier>[_<location>][/<component>],
// the component being optional, and for a suggested binding the runtime picks the component itself (the rules are
// in "Suggested Bindings": click else value for boolean actions, value else click for float, x and y for vector2f,
// pose for pose). So an identifier path is accepted on a top-level path when the profile lists at least one of its
// components there (touch: /user/hand/left/input/x yes, /user/hand/right/input/x no); whether it then suits the
// action's type is left to binding. Output paths (/output/<identifier>[_<location>]) have no component.
bool is_supported_binding(const InteractionProfile& profile, std::string_view binding) {
  for (std::string_view full : profile.binding_paths) {
    if (full == binding || is_identifier_of(full, binding)) return true;
  }
  return false;
}

}  // namespace foveart::sim
