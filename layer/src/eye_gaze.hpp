// XR_EXT_eye_gaze_interaction as the layer's gaze source, done the way a
// runtime-side layer must: the layer enables the extension below itself when
// the app did not (and hides it from the app), owns an action set with one
// pose action bound to /user/eyes_ext/input/gaze_ext/pose, merges its binding
// into the app's suggestions for the eye gaze profile, rides along the app's
// xrAttachSessionActionSets and xrSyncActions (or attaches / syncs alone when
// the app never does), and locates the gaze action space at display time.
#pragma once

#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "dispatch.hpp"

namespace foveart::layer {

inline constexpr const char* kEyeGazeProfilePath = "/interaction_profiles/ext/eye_gaze_interaction";
inline constexpr const char* kEyeGazePosePath = "/user/eyes_ext/input/gaze_ext/pose";
inline constexpr const char* kEyesUserPath = "/user/eyes_ext";
inline constexpr const char* kLayerActionSetName = "xr_apilayer_foveart_gaze";

// Per instance: the layer's action set and what it knows of the extension.
struct EyeGazeActions {
  bool extension_enabled = false;  // XR_EXT_eye_gaze_interaction is enabled below the layer
  bool hidden_from_app = false;    // ... by the layer; the app did not enable it
  std::string unavailable_reason;  // why not, for the log of a renderer that asks for it
  XrActionSet action_set = XR_NULL_HANDLE;
  XrAction pose_action = XR_NULL_HANDLE;
  XrPath profile = XR_NULL_PATH;
  XrPath gaze_pose = XR_NULL_PATH;
  XrPath eyes_user = XR_NULL_PATH;
  bool ready() const { return action_set != XR_NULL_HANDLE && pose_action != XR_NULL_HANDLE; }
};

// Whether the next layer / runtime lists `extension` in
// xrEnumerateInstanceExtensionProperties (asked through next_gipa with no
// instance). *answered = false when the chain could not be asked.
bool next_offers_extension(PFN_xrGetInstanceProcAddr next_gipa, const char* extension, bool* answered);

// After instance creation: the action set, the pose action and the first
// suggestion for the eye gaze profile. On failure logs and leaves !ready().
void create_eye_gaze_actions(XrInstance instance, PFN_xrGetInstanceProcAddr next_gipa, EyeGazeActions* out);

// Per session: the action space and who attached / synced what.
class SessionEyeGaze {
 public:
  SessionEyeGaze(XrSession session, const EyeGazeActions& actions, PFN_xrGetInstanceProcAddr next_gipa,
                 XrInstance instance);

  XrActionSet action_set() const { return action_set_; }

  // The app's xrAttachSessionActionSets: the sets to attach with the layer's
  // appended; call attached() with the result.
  std::vector<XrActionSet> sets_to_attach(const XrSessionActionSetsAttachInfo& app, bool* layer_already_attached);
  void app_attached(XrResult result);
  // The app's xrSyncActions: the active sets with the layer's appended (when attached).
  std::vector<XrActiveActionSet> sets_to_sync(const XrActionsSyncInfo& app);
  void app_synced(XrResult result);

  struct Gaze {
    bool valid = false;
    XrPosef pose_in_space{};  // gaze ray: origin between the eyes, -z along the gaze
    XrTime sample_time = 0;   // XrEyeGazeSampleTimeEXT (0 when the runtime gives none)
    std::string problem;      // why not valid, for a log line
  };
  // Attaches (if the app has not) and syncs (if the app never does), then
  // locates the gaze in `space` at `time`.
  Gaze locate(XrSpace space, XrTime time);

 private:
  XrSession session_;
  XrActionSet action_set_;
  PFN_xrAttachSessionActionSets attach_ = nullptr;
  PFN_xrSyncActions sync_ = nullptr;
  PFN_xrLocateSpace locate_ = nullptr;
  XrSpace space_ = XR_NULL_HANDLE;
  std::mutex mutex_;
  bool attached_ = false;         // the layer's set is attached to the session
  bool app_ever_synced_ = false;  // the app called xrSyncActions successfully (with the layer's set)
};

}  // namespace foveart::layer
