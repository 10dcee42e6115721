#include "eye_gaze.hpp"

#include <cstring>

#include "log.hpp"

namespace foveart::layer {
namespace {

template <class Fn>
Fn next_fn(PFN_xrGetInstanceProcAddr gipa, XrInstance instance, const char* name) {
  PFN_xrVoidFunction fn = nullptr;
  if (gipa == nullptr || XR_FAILED(gipa(instance, name, &fn))) return nullptr;
  return reinterpret_cast<Fn>(fn);
}

}  // namespace

bool next_offers_extension(PFN_xrGetInstanceProcAddr next_gipa, const char* extension, bool* answered) {
  *answered = false;
  auto enumerate = next_fn<PFN_xrEnumerateInstanceExtensionProperties>(next_gipa, XR_NULL_HANDLE,
                                                                       "xrEnumerateInstanceExtensionProperties");
  if (enumerate == nullptr) return false;
  uint32_t count = 0;
  if (XR_FAILED(enumerate(nullptr, 0, &count, nullptr))) return false;
  std::vector<XrExtensionProperties> props(count, XrExtensionProperties{XR_TYPE_EXTENSION_PROPERTIES, nullptr, {}, 0});
  if (XR_FAILED(enumerate(nullptr, count, &count, props.data()))) return false;
  *answered = true;
  for (uint32_t i = 0; i < count && i < props.size(); ++i) {
    if (strncmp(props[i].extensionName, extension, XR_MAX_EXTENSION_NAME_SIZE) == 0) return true;
  }
  return false;
}

void create_eye_gaze_actions(XrInstance instance, PFN_xrGetInstanceProcAddr next_gipa, EyeGazeActions* out) {
  auto string_to_path = next_fn<PFN_xrStringToPath>(next_gipa, instance, "xrStringToPath");
  auto create_set = next_fn<PFN_xrCreateActionSet>(next_gipa, instance, "xrCreateActionSet");
  auto destroy_set = next_fn<PFN_xrDestroyActionSet>(next_gipa, instance, "xrDestroyActionSet");
  auto create_action = next_fn<PFN_xrCreateAction>(next_gipa, instance, "xrCreateAction");
  auto suggest = next_fn<PFN_xrSuggestInteractionProfileBindings>(next_gipa, instance,
                                                                  "xrSuggestInteractionProfileBindings");
  auto fail = [&](const std::string& why) {
    out->unavailable_reason = why;
    log(LogLevel::Warn, "XR_EXT_eye_gaze_interaction: ", why, "; gaze source eye_gaze_interaction will use fixed "
                        "foveation");
    if (out->action_set != XR_NULL_HANDLE && destroy_set != nullptr) destroy_set(out->action_set);
    out->action_set = XR_NULL_HANDLE;
    out->pose_action = XR_NULL_HANDLE;
  };
  if (string_to_path == nullptr || create_set == nullptr || create_action == nullptr || suggest == nullptr) {
    return fail("the next layer/runtime lacks the action functions");
  }
  if (XR_FAILED(string_to_path(instance, kEyeGazeProfilePath, &out->profile)) ||
      XR_FAILED(string_to_path(instance, kEyeGazePosePath, &out->gaze_pose)) ||
      XR_FAILED(string_to_path(instance, kEyesUserPath, &out->eyes_user))) {
    return fail("xrStringToPath failed for the eye gaze paths");
  }
  XrActionSetCreateInfo set_info{XR_TYPE_ACTION_SET_CREATE_INFO, nullptr, {}, {}, 0};
  std::strncpy(set_info.actionSetName, kLayerActionSetName, XR_MAX_ACTION_SET_NAME_SIZE - 1);
  std::strncpy(set_info.localizedActionSetName, "FoveaRT layer gaze", XR_MAX_LOCALIZED_ACTION_SET_NAME_SIZE - 1);
  if (const XrResult r = create_set(instance, &set_info, &out->action_set); XR_FAILED(r)) {
    out->action_set = XR_NULL_HANDLE;
    return fail("xrCreateActionSet failed (XrResult " + std::to_string(r) + ")");
  }
  XrActionCreateInfo action_info{XR_TYPE_ACTION_CREATE_INFO, nullptr, {}, XR_ACTION_TYPE_POSE_INPUT, 0, nullptr, {}};
  std::strncpy(action_info.actionName, "gaze_pose", XR_MAX_ACTION_NAME_SIZE - 1);
  std::strncpy(action_info.localizedActionName, "FoveaRT gaze pose", XR_MAX_LOCALIZED_ACTION_NAME_SIZE - 1);
  if (const XrResult r = create_action(out->action_set, &action_info, &out->pose_action); XR_FAILED(r)) {
    return fail("xrCreateAction failed (XrResult " + std::to_string(r) + ")");
  }
  // Suggestions replace earlier ones per profile: the app's own suggestion for
  // this profile gets the layer's binding merged in (hook_xrSuggestInteractionProfileBindings).
  const XrActionSuggestedBinding binding{out->pose_action, out->gaze_pose};
  const XrInteractionProfileSuggestedBinding suggested{XR_TYPE_INTERACTION_PROFILE_SUGGESTED_BINDING, nullptr,
                                                       out->profile, 1, &binding};
  if (const XrResult r = suggest(instance, &suggested); XR_FAILED(r)) {
    return fail("xrSuggestInteractionProfileBindings for " + std::string(kEyeGazeProfilePath) +
                " failed (XrResult " + std::to_string(r) + ")");
  }
  log(LogLevel::Info, "XR_EXT_eye_gaze_interaction: action set '", kLayerActionSetName, "' bound to ",
      kEyeGazePosePath, out->hidden_from_app ? " (extension enabled by the layer, hidden from the app)" : "");
}

SessionEyeGaze::SessionEyeGaze(XrSession session, const EyeGazeActions& actions, PFN_xrGetInstanceProcAddr next_gipa,
                               XrInstance instance)
    : session_(session), action_set_(actions.action_set) {
  attach_ = next_fn<PFN_xrAttachSessionActionSets>(next_gipa, instance, "xrAttachSessionActionSets");
  sync_ = next_fn<PFN_xrSyncActions>(next_gipa, instance, "xrSyncActions");
  locate_ = next_fn<PFN_xrLocateSpace>(next_gipa, instance, "xrLocateSpace");
  auto create_space = next_fn<PFN_xrCreateActionSpace>(next_gipa, instance, "xrCreateActionSpace");
  if (create_space == nullptr) return;
  XrActionSpaceCreateInfo info{XR_TYPE_ACTION_SPACE_CREATE_INFO, nullptr, actions.pose_action, XR_NULL_PATH,
                               {{0.0f, 0.0f, 0.0f, 1.0f}, {0.0f, 0.0f, 0.0f}}};
  if (const XrResult r = create_space(session, &info, &space_); XR_FAILED(r)) {
    log(LogLevel::Warn, "XR_EXT_eye_gaze_interaction: xrCreateActionSpace failed (XrResult ", r, ")");
    space_ = XR_NULL_HANDLE;
  }
}

std::vector<XrActionSet> SessionEyeGaze::sets_to_attach(const XrSessionActionSetsAttachInfo& app,
                                                        bool* layer_already_attached) {
  std::lock_guard lock(mutex_);
  std::vector<XrActionSet> sets;
  if (app.actionSets != nullptr) sets.assign(app.actionSets, app.actionSets + app.countActionSets);
  *layer_already_attached = attached_;
  if (!attached_) sets.push_back(action_set_);
  return sets;
}

void SessionEyeGaze::app_attached(XrResult result) {
  std::lock_guard lock(mutex_);
  if (XR_SUCCEEDED(result)) attached_ = true;
}

std::vector<XrActiveActionSet> SessionEyeGaze::sets_to_sync(const XrActionsSyncInfo& app) {
  std::lock_guard lock(mutex_);
  std::vector<XrActiveActionSet> sets;
  if (app.activeActionSets != nullptr) sets.assign(app.activeActionSets, app.activeActionSets + app.countActiveActionSets);
  if (attached_) sets.push_back(XrActiveActionSet{action_set_, XR_NULL_PATH});
  return sets;
}

void SessionEyeGaze::app_synced(XrResult result) {
  std::lock_guard lock(mutex_);
  if (XR_SUCCEEDED(result) && attached_) app_ever_synced_ = true;
}

SessionEyeGaze::Gaze SessionEyeGaze::locate(XrSpace space, XrTime time) {
  Gaze out;
  std::lock_guard lock(mutex_);
  if (space_ == XR_NULL_HANDLE || attach_ == nullptr || sync_ == nullptr || locate_ == nullptr) {
    out.problem = "no gaze action space";
    return out;
  }
  if (!attached_) {
    // The app attached nothing before its first foveated frame: attach alone.
    const XrSessionActionSetsAttachInfo info{XR_TYPE_SESSION_ACTION_SETS_ATTACH_INFO, nullptr, 1, &action_set_};
    const XrResult r = attach_(session_, &info);
    if (XR_FAILED(r)) {
      out.problem = "xrAttachSessionActionSets failed (XrResult " + std::to_string(r) + ")";
      return out;
    }
    attached_ = true;
    log(LogLevel::Info, "XR_EXT_eye_gaze_interaction: the app attached no action sets before its first foveated "
                        "frame; the layer attached its own (an app attaching later gets "
                        "XR_ERROR_ACTIONSETS_ALREADY_ATTACHED)");
  }
  if (!app_ever_synced_) {
    // The app never syncs: the layer syncs its own set each frame. An app that
    // synced once keeps the action active; re-syncing for it would eat the
    // changedSinceLastSync edges of its own actions.
    const XrActiveActionSet active{action_set_, XR_NULL_PATH};
    const XrActionsSyncInfo info{XR_TYPE_ACTIONS_SYNC_INFO, nullptr, 1, &active};
    const XrResult r = sync_(session_, &info);
    if (XR_FAILED(r)) {
      out.problem = "xrSyncActions failed (XrResult " + std::to_string(r) + ")";
      return out;
    }
  }
  XrEyeGazeSampleTimeEXT sample_time{XR_TYPE_EYE_GAZE_SAMPLE_TIME_EXT, nullptr, 0};
  XrSpaceLocation location{XR_TYPE_SPACE_LOCATION, &sample_time, 0, {{0.0f, 0.0f, 0.0f, 1.0f}, {0.0f, 0.0f, 0.0f}}};
  const XrResult r = locate_(space_, space, time, &location);
  if (XR_FAILED(r)) {
    out.problem = "xrLocateSpace failed (XrResult " + std::to_string(r) + ")";
    return out;
  }
  constexpr XrSpaceLocationFlags kNeeded = XR_SPACE_LOCATION_ORIENTATION_VALID_BIT | XR_SPACE_LOCATION_ORIENTATION_TRACKED_BIT;
  if ((location.locationFlags & kNeeded) != kNeeded) {
    out.problem = "gaze not tracked";
    return out;
  }
  out.valid = true;
  out.pose_in_space = location.pose;
  out.sample_time = sample_time.time;
  return out;
}

}  // namespace foveart::layer
