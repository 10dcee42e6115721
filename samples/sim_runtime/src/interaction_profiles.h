// Interaction profiles and binding paths: OpenXR 1.0 specification, section 6.4, and XR_EXT_eye_gaze_interaction.
#pragma once

#include <string_view>
#include <vector>

namespace foveart::sim {

struct InteractionProfile {
  std::string_view path;                          // "/interaction_profiles/khr/simple_controller"
  std::string_view extension;                     // "" for core profiles, else the extension that must be enabled
  std::vector<std::string_view> top_level_paths;  // subaction paths, e.g. "/user/hand/left"
  std::vector<std::string_view> binding_paths;    // every full binding path, components included
};

// Every profile the spec lists (core + XR_EXT_eye_gaze_interaction).
const std::vector<InteractionProfile>& interaction_profiles();

// The profile named by `path`, or nullptr.
const InteractionProfile* find_interaction_profile(std::string_view path);

// True when the spec lists `binding` for `profile` (a full path, or an identifier path whose component is omitted,
// per 6.3.2).
bool is_supported_binding(const InteractionProfile& profile, std::string_view binding);

}  // namespace foveart::sim
