// The action system, as far as an eye tracker needs it: action sets and actions,
// suggested bindings checked against the spec's profiles (interaction_profiles.h; the eye
// gaze profile live, controller profiles accepted and inactive, since the FOVE 0 has no
// controllers), attach, sync, state queries, haptics accepted and ignored.
#include <cstring>

#include "api_common.h"
#include "interaction_profiles.h"

namespace foveart::sim {
namespace {

constexpr const char* kEyeGazeProfile = "/interaction_profiles/ext/eye_gaze_interaction";
constexpr const char* kEyeGazePose = "/user/eyes_ext/input/gaze_ext/pose";
constexpr const char* kEyesUser = "/user/eyes_ext";

// OpenXR 1.0, section 6.3.1 "Reserved Paths": the top-level /user paths, and /user/eyes_ext
// where XR_EXT_eye_gaze_interaction is enabled.
bool is_top_level_user_path(const Instance& inst, const std::string& p) {
  static const char* kPaths[] = {"/user/hand/left", "/user/hand/right", "/user/head", "/user/gamepad",
                                 "/user/treadmill"};
  for (const char* k : kPaths) {
    if (p == k) return true;
  }
  return inst.ext_eye_gaze && p == kEyesUser;
}

// Whether the app enabled the extension a profile needs ("" for core profiles).
bool profile_enabled(const Instance& inst, const InteractionProfile& profile) {
  if (profile.extension.empty()) return true;
  return profile.extension == XR_EXT_EYE_GAZE_INTERACTION_EXTENSION_NAME && inst.ext_eye_gaze;
}

XRAPI_ATTR XrResult XRAPI_CALL create_action_set(XrInstance instance,
                                                 const XrActionSetCreateInfo* info,
                                                 XrActionSet* out) {
  return guarded("xrCreateActionSet", [&]() -> XrResult {
    FOVEART_LOCK_INSTANCE(instance);
    (void)inst;
    FOVEART_CHECK_STRUCT(info, XR_TYPE_ACTION_SET_CREATE_INFO);
    if (out == nullptr) return XR_ERROR_VALIDATION_FAILURE;
    // OpenXR 1.0, xrCreateActionSet: an empty name is NAME_INVALID, a malformed one PATH_FORMAT_INVALID.
    if (info->actionSetName[0] == '\0') return XR_ERROR_NAME_INVALID;
    if (!is_well_formed_name(info->actionSetName, XR_MAX_ACTION_SET_NAME_SIZE))
      return XR_ERROR_PATH_FORMAT_INVALID;
    if (strnlen(info->localizedActionSetName, XR_MAX_LOCALIZED_ACTION_SET_NAME_SIZE) == 0) {
      return XR_ERROR_LOCALIZED_NAME_INVALID;
    }
    for (auto& [id, set] : rt.action_sets) {
      if (set->name == info->actionSetName) return XR_ERROR_NAME_DUPLICATED;
      if (set->localized_name == info->localizedActionSetName)
        return XR_ERROR_LOCALIZED_NAME_DUPLICATED;
    }
    auto set = std::make_unique<ActionSet>();
    set->id = rt.next_id++;
    set->name = info->actionSetName;
    set->localized_name = info->localizedActionSetName;
    set->priority = info->priority;
    *out = to_handle<XrActionSet>(set->id);
    rt.action_sets.emplace(set->id, std::move(set));
    return XR_SUCCESS;
  });
}

XRAPI_ATTR XrResult XRAPI_CALL destroy_action_set(XrActionSet handle) {
  return guarded("xrDestroyActionSet", [&]() -> XrResult {
    Runtime& rt = runtime();
    std::lock_guard<std::mutex> lock(rt.mutex);
    ActionSet* set = find(rt.action_sets, handle);
    if (set == nullptr) return XR_ERROR_HANDLE_INVALID;
    for (XrAction a : set->actions) rt.actions.erase(handle_id(a));
    rt.action_sets.erase(handle_id(handle));
    return XR_SUCCESS;
  });
}

XRAPI_ATTR XrResult XRAPI_CALL create_action(XrActionSet set_handle, const XrActionCreateInfo* info,
                                             XrAction* out) {
  return guarded("xrCreateAction", [&]() -> XrResult {
    Runtime& rt = runtime();
    std::lock_guard<std::mutex> lock(rt.mutex);
    ActionSet* set = find(rt.action_sets, set_handle);
    if (set == nullptr || !rt.instance) return XR_ERROR_HANDLE_INVALID;
    FOVEART_CHECK_STRUCT(info, XR_TYPE_ACTION_CREATE_INFO);
    if (out == nullptr) return XR_ERROR_VALIDATION_FAILURE;
    if (set->attached) return XR_ERROR_ACTIONSETS_ALREADY_ATTACHED;
    // OpenXR 1.0, xrCreateAction: an empty name is NAME_INVALID, a malformed one PATH_FORMAT_INVALID.
    if (info->actionName[0] == '\0') return XR_ERROR_NAME_INVALID;
    if (!is_well_formed_name(info->actionName, XR_MAX_ACTION_NAME_SIZE))
      return XR_ERROR_PATH_FORMAT_INVALID;
    if (strnlen(info->localizedActionName, XR_MAX_LOCALIZED_ACTION_NAME_SIZE) == 0) {
      return XR_ERROR_LOCALIZED_NAME_INVALID;
    }
    switch (info->actionType) {
      case XR_ACTION_TYPE_BOOLEAN_INPUT:
      case XR_ACTION_TYPE_FLOAT_INPUT:
      case XR_ACTION_TYPE_VECTOR2F_INPUT:
      case XR_ACTION_TYPE_POSE_INPUT:
      case XR_ACTION_TYPE_VIBRATION_OUTPUT:
        break;
      default:
        return XR_ERROR_VALIDATION_FAILURE;
    }
    for (XrAction a : set->actions) {
      const Action* other = find(rt.actions, a);
      if (other->name == info->actionName) return XR_ERROR_NAME_DUPLICATED;
      if (other->localized_name == info->localizedActionName)
        return XR_ERROR_LOCALIZED_NAME_DUPLICATED;
    }
    if (info->countSubactionPaths > 0 && info->subactionPaths == nullptr) return XR_ERROR_VALIDATION_FAILURE;
    auto action = std::make_unique<Action>();
    for (uint32_t i = 0; i < info->countSubactionPaths; ++i) {
      const std::string* p = path_string(*rt.instance, info->subactionPaths[i]);
      if (p == nullptr) return XR_ERROR_PATH_INVALID;
      if (!is_top_level_user_path(*rt.instance, *p)) return XR_ERROR_PATH_UNSUPPORTED;
      // OpenXR 1.0, xrCreateAction: a subaction path listed twice is PATH_UNSUPPORTED.
      if (std::find(action->subaction_paths.begin(), action->subaction_paths.end(), info->subactionPaths[i]) !=
          action->subaction_paths.end()) {
        return XR_ERROR_PATH_UNSUPPORTED;
      }
      action->subaction_paths.push_back(info->subactionPaths[i]);
    }
    action->id = rt.next_id++;
    action->set = set_handle;
    action->name = info->actionName;
    action->localized_name = info->localizedActionName;
    action->type = info->actionType;
    *out = to_handle<XrAction>(action->id);
    set->actions.push_back(*out);
    rt.actions.emplace(action->id, std::move(action));
    return XR_SUCCESS;
  });
}

XRAPI_ATTR XrResult XRAPI_CALL destroy_action(XrAction handle) {
  return guarded("xrDestroyAction", [&]() -> XrResult {
    Runtime& rt = runtime();
    std::lock_guard<std::mutex> lock(rt.mutex);
    Action* action = find(rt.actions, handle);
    if (action == nullptr) return XR_ERROR_HANDLE_INVALID;
    if (ActionSet* set = find(rt.action_sets, action->set)) {
      std::erase(set->actions, handle);
    }
    rt.actions.erase(handle_id(handle));
    return XR_SUCCESS;
  });
}

XRAPI_ATTR XrResult XRAPI_CALL suggest_bindings(XrInstance instance,
                                                const XrInteractionProfileSuggestedBinding* info) {
  return guarded("xrSuggestInteractionProfileBindings", [&]() -> XrResult {
    FOVEART_LOCK_INSTANCE(instance);
    FOVEART_CHECK_STRUCT(info, XR_TYPE_INTERACTION_PROFILE_SUGGESTED_BINDING);
    if (info->countSuggestedBindings == 0 || info->suggestedBindings == nullptr)
      return XR_ERROR_VALIDATION_FAILURE;
    const std::string* profile_name = path_string(*inst, info->interactionProfile);
    if (profile_name == nullptr) return XR_ERROR_PATH_INVALID;
    // OpenXR 1.0, xrSuggestInteractionProfileBindings: a profile the runtime does not offer, or a
    // binding path the profile does not list (section 6.4), is PATH_UNSUPPORTED.
    const InteractionProfile* profile = find_interaction_profile(*profile_name);
    if (profile == nullptr || !profile_enabled(*inst, *profile)) return XR_ERROR_PATH_UNSUPPORTED;
    std::vector<std::pair<XrAction, XrPath>> bindings;
    for (uint32_t i = 0; i < info->countSuggestedBindings; ++i) {
      const XrActionSuggestedBinding& b = info->suggestedBindings[i];
      Action* action = find(rt.actions, b.action);
      if (action == nullptr) return XR_ERROR_HANDLE_INVALID;
      ActionSet* set = find(rt.action_sets, action->set);
      if (set != nullptr && set->attached) return XR_ERROR_ACTIONSETS_ALREADY_ATTACHED;
      const std::string* path = path_string(*inst, b.binding);
      if (path == nullptr) return XR_ERROR_PATH_INVALID;
      if (!is_supported_binding(*profile, *path)) return XR_ERROR_PATH_UNSUPPORTED;
      bindings.emplace_back(b.action, b.binding);
    }
    inst->suggested[info->interactionProfile] =
        std::move(bindings);  // replaces earlier suggestions
    return XR_SUCCESS;
  });
}

XRAPI_ATTR XrResult XRAPI_CALL attach_action_sets(XrSession handle,
                                                  const XrSessionActionSetsAttachInfo* info) {
  return guarded("xrAttachSessionActionSets", [&]() -> XrResult {
    FOVEART_LOCK_SESSION(handle);
    FOVEART_CHECK_STRUCT(info, XR_TYPE_SESSION_ACTION_SETS_ATTACH_INFO);
    if (info->countActionSets == 0 || info->actionSets == nullptr)
      return XR_ERROR_VALIDATION_FAILURE;
    if (!session->attached_sets.empty()) return XR_ERROR_ACTIONSETS_ALREADY_ATTACHED;
    for (uint32_t i = 0; i < info->countActionSets; ++i) {
      if (find(rt.action_sets, info->actionSets[i]) == nullptr) return XR_ERROR_HANDLE_INVALID;
    }
    const XrPath eye_profile = intern_path(*inst, kEyeGazeProfile);
    for (uint32_t i = 0; i < info->countActionSets; ++i) {
      ActionSet* set = find(rt.action_sets, info->actionSets[i]);
      set->attached = true;
      session->attached_sets.push_back(info->actionSets[i]);
      for (XrAction a : set->actions) {
        Action* action = find(rt.actions, a);
        auto it = inst->suggested.find(eye_profile);
        if (it == inst->suggested.end()) continue;
        // Only a pose action takes the gaze pose; a binding of another type is suggested but unbound.
        for (auto& [bound, path] : it->second) {
          if (bound == a && action->type == XR_ACTION_TYPE_POSE_INPUT) action->bound_to_eye_gaze = true;
        }
        session->eye_gaze_bound |= action->bound_to_eye_gaze;
      }
    }
    if (session->eye_gaze_bound && inst->config.eye_tracking) {
      XrEventDataBuffer buffer{};
      buffer.type = XR_TYPE_EVENT_DATA_BUFFER;
      auto* e = reinterpret_cast<XrEventDataInteractionProfileChanged*>(&buffer);
      e->type = XR_TYPE_EVENT_DATA_INTERACTION_PROFILE_CHANGED;
      e->next = nullptr;
      e->session = handle;
      push_event(*inst, buffer);
    }
    return XR_SUCCESS;
  });
}

XRAPI_ATTR XrResult XRAPI_CALL get_current_interaction_profile(XrSession handle, XrPath top_level,
                                                               XrInteractionProfileState* state) {
  return guarded("xrGetCurrentInteractionProfile", [&]() -> XrResult {
    FOVEART_LOCK_SESSION(handle);
    FOVEART_CHECK_STRUCT(state, XR_TYPE_INTERACTION_PROFILE_STATE);
    if (session->attached_sets.empty()) return XR_ERROR_ACTIONSET_NOT_ATTACHED;
    const std::string* path = path_string(*inst, top_level);
    if (path == nullptr) return XR_ERROR_PATH_INVALID;
    state->interactionProfile = XR_NULL_PATH;
    if (*path == kEyesUser && session->eye_gaze_bound && inst->config.eye_tracking) {
      state->interactionProfile = intern_path(*inst, kEyeGazeProfile);
    }
    return XR_SUCCESS;
  });
}

XRAPI_ATTR XrResult XRAPI_CALL sync_actions(XrSession handle, const XrActionsSyncInfo* info) {
  return guarded("xrSyncActions", [&]() -> XrResult {
    FOVEART_LOCK_SESSION(handle);
    FOVEART_CHECK_STRUCT(info, XR_TYPE_ACTIONS_SYNC_INFO);
    if (info->countActiveActionSets > 0 && info->activeActionSets == nullptr)
      return XR_ERROR_VALIDATION_FAILURE;
    for (uint32_t i = 0; i < info->countActiveActionSets; ++i) {
      ActionSet* set = find(rt.action_sets, info->activeActionSets[i].actionSet);
      if (set == nullptr) return XR_ERROR_HANDLE_INVALID;
      if (std::find(session->attached_sets.begin(), session->attached_sets.end(),
                    info->activeActionSets[i].actionSet) == session->attached_sets.end()) {
        return XR_ERROR_ACTIONSET_NOT_ATTACHED;
      }
    }
    const bool focused = session->state == XR_SESSION_STATE_FOCUSED;
    for (XrActionSet s : session->attached_sets) {
      ActionSet* set = find(rt.action_sets, s);
      if (set == nullptr) continue;
      bool active_set = false;
      for (uint32_t i = 0; i < info->countActiveActionSets; ++i)
        active_set |= info->activeActionSets[i].actionSet == s;
      for (XrAction a : set->actions) {
        Action* action = find(rt.actions, a);
        action->active =
            focused && active_set && action->bound_to_eye_gaze && inst->config.eye_tracking;
      }
    }
    return focused ? XR_SUCCESS : XR_SESSION_NOT_FOCUSED;
  });
}

// An action of an attached set, of `type`, and a subaction path it was created with
// (OpenXR 1.0: a subaction path that is no path at all is PATH_INVALID, one the action
// lacks PATH_UNSUPPORTED). For the state queries and the haptics alike.
XrResult find_attached_action(Runtime& rt, const Session& session, XrAction handle, XrActionType type,
                              XrPath subaction_path, Action** out) {
  Action* action = find(rt.actions, handle);
  if (action == nullptr) return XR_ERROR_HANDLE_INVALID;
  if (std::find(session.attached_sets.begin(), session.attached_sets.end(), action->set) ==
      session.attached_sets.end()) {
    return XR_ERROR_ACTIONSET_NOT_ATTACHED;
  }
  if (action->type != type) return XR_ERROR_ACTION_TYPE_MISMATCH;
  if (subaction_path != XR_NULL_PATH) {
    if (path_string(*rt.instance, subaction_path) == nullptr) return XR_ERROR_PATH_INVALID;
    if (std::find(action->subaction_paths.begin(), action->subaction_paths.end(), subaction_path) ==
        action->subaction_paths.end()) {
      return XR_ERROR_PATH_UNSUPPORTED;
    }
  }
  *out = action;
  return XR_SUCCESS;
}

// Common checks of the xrGetActionState* functions.
XrResult lookup_action(Runtime& rt, Session& session, const XrActionStateGetInfo* info,
                       XrActionType type, Action** out) {
  FOVEART_CHECK_STRUCT(info, XR_TYPE_ACTION_STATE_GET_INFO);
  return find_attached_action(rt, session, info->action, type, info->subactionPath, out);
}

XRAPI_ATTR XrResult XRAPI_CALL get_state_boolean(XrSession handle, const XrActionStateGetInfo* info,
                                                 XrActionStateBoolean* state) {
  return guarded("xrGetActionStateBoolean", [&]() -> XrResult {
    FOVEART_LOCK_SESSION(handle);
    (void)inst;
    FOVEART_CHECK_STRUCT(state, XR_TYPE_ACTION_STATE_BOOLEAN);
    Action* action = nullptr;
    if (XrResult r = lookup_action(rt, *session, info, XR_ACTION_TYPE_BOOLEAN_INPUT, &action);
        r != XR_SUCCESS)
      return r;
    state->currentState = XR_FALSE;
    state->changedSinceLastSync = XR_FALSE;
    state->lastChangeTime = 0;
    state->isActive = XR_FALSE;  // no controllers on a FOVE 0
    return XR_SUCCESS;
  });
}

XRAPI_ATTR XrResult XRAPI_CALL get_state_float(XrSession handle, const XrActionStateGetInfo* info,
                                               XrActionStateFloat* state) {
  return guarded("xrGetActionStateFloat", [&]() -> XrResult {
    FOVEART_LOCK_SESSION(handle);
    (void)inst;
    FOVEART_CHECK_STRUCT(state, XR_TYPE_ACTION_STATE_FLOAT);
    Action* action = nullptr;
    if (XrResult r = lookup_action(rt, *session, info, XR_ACTION_TYPE_FLOAT_INPUT, &action);
        r != XR_SUCCESS)
      return r;
    state->currentState = 0.0F;
    state->changedSinceLastSync = XR_FALSE;
    state->lastChangeTime = 0;
    state->isActive = XR_FALSE;
    return XR_SUCCESS;
  });
}

XRAPI_ATTR XrResult XRAPI_CALL get_state_vector2f(XrSession handle,
                                                  const XrActionStateGetInfo* info,
                                                  XrActionStateVector2f* state) {
  return guarded("xrGetActionStateVector2f", [&]() -> XrResult {
    FOVEART_LOCK_SESSION(handle);
    (void)inst;
    FOVEART_CHECK_STRUCT(state, XR_TYPE_ACTION_STATE_VECTOR2F);
    Action* action = nullptr;
    if (XrResult r = lookup_action(rt, *session, info, XR_ACTION_TYPE_VECTOR2F_INPUT, &action);
        r != XR_SUCCESS)
      return r;
    state->currentState = {0.0F, 0.0F};
    state->changedSinceLastSync = XR_FALSE;
    state->lastChangeTime = 0;
    state->isActive = XR_FALSE;
    return XR_SUCCESS;
  });
}

XRAPI_ATTR XrResult XRAPI_CALL get_state_pose(XrSession handle, const XrActionStateGetInfo* info,
                                              XrActionStatePose* state) {
  return guarded("xrGetActionStatePose", [&]() -> XrResult {
    FOVEART_LOCK_SESSION(handle);
    FOVEART_CHECK_STRUCT(state, XR_TYPE_ACTION_STATE_POSE);
    Action* action = nullptr;
    if (XrResult r = lookup_action(rt, *session, info, XR_ACTION_TYPE_POSE_INPUT, &action);
        r != XR_SUCCESS)
      return r;
    bool active = action->active;
    if (info->subactionPath != XR_NULL_PATH)
      active = active && *path_string(*inst, info->subactionPath) == kEyesUser;
    state->isActive = active ? XR_TRUE : XR_FALSE;
    return XR_SUCCESS;
  });
}

XRAPI_ATTR XrResult XRAPI_CALL
enumerate_bound_sources(XrSession handle, const XrBoundSourcesForActionEnumerateInfo* info,
                        uint32_t capacity, uint32_t* count, XrPath* sources) {
  return guarded("xrEnumerateBoundSourcesForAction", [&]() -> XrResult {
    FOVEART_LOCK_SESSION(handle);
    FOVEART_CHECK_STRUCT(info, XR_TYPE_BOUND_SOURCES_FOR_ACTION_ENUMERATE_INFO);
    Action* action = find(rt.actions, info->action);
    if (action == nullptr) return XR_ERROR_HANDLE_INVALID;
    if (session->attached_sets.empty()) return XR_ERROR_ACTIONSET_NOT_ATTACHED;
    std::vector<XrPath> out;
    if (action->bound_to_eye_gaze && inst->config.eye_tracking)
      out.push_back(intern_path(*inst, kEyeGazePose));
    return two_call(capacity, count, sources, out);
  });
}

XRAPI_ATTR XrResult XRAPI_CALL
get_input_source_localized_name(XrSession handle, const XrInputSourceLocalizedNameGetInfo* info,
                                uint32_t capacity, uint32_t* count, char* buffer) {
  return guarded("xrGetInputSourceLocalizedName", [&]() -> XrResult {
    FOVEART_LOCK_SESSION(handle);
    FOVEART_CHECK_STRUCT(info, XR_TYPE_INPUT_SOURCE_LOCALIZED_NAME_GET_INFO);
    // OpenXR 1.0, xrGetInputSourceLocalizedName: before xrAttachSessionActionSets there
    // are no input sources to name.
    if (session->attached_sets.empty()) return XR_ERROR_ACTIONSET_NOT_ATTACHED;
    if (path_string(*inst, info->sourcePath) == nullptr) return XR_ERROR_PATH_INVALID;
    if (info->whichComponents == 0) return XR_ERROR_VALIDATION_FAILURE;
    return two_call_string(capacity, count, buffer, "FOVE 0 eye tracker");
  });
}

XrResult check_haptic(Runtime& rt, Session& session, const XrHapticActionInfo* info) {
  FOVEART_CHECK_STRUCT(info, XR_TYPE_HAPTIC_ACTION_INFO);
  Action* action = nullptr;
  return find_attached_action(rt, session, info->action, XR_ACTION_TYPE_VIBRATION_OUTPUT, info->subactionPath,
                              &action);
}

XRAPI_ATTR XrResult XRAPI_CALL apply_haptic(XrSession handle, const XrHapticActionInfo* info,
                                            const XrHapticBaseHeader* feedback) {
  return guarded("xrApplyHapticFeedback", [&]() -> XrResult {
    FOVEART_LOCK_SESSION(handle);
    (void)inst;
    if (feedback == nullptr) return XR_ERROR_VALIDATION_FAILURE;
    if (XrResult r = check_haptic(rt, *session, info); r != XR_SUCCESS) return r;
    return session->state == XR_SESSION_STATE_FOCUSED ? XR_SUCCESS : XR_SESSION_NOT_FOCUSED;
  });
}

XRAPI_ATTR XrResult XRAPI_CALL stop_haptic(XrSession handle, const XrHapticActionInfo* info) {
  return guarded("xrStopHapticFeedback", [&]() -> XrResult {
    FOVEART_LOCK_SESSION(handle);
    (void)inst;
    if (XrResult r = check_haptic(rt, *session, info); r != XR_SUCCESS) return r;
    return session->state == XR_SESSION_STATE_FOCUSED ? XR_SUCCESS : XR_SESSION_NOT_FOCUSED;
  });
}

}  // namespace

void register_action_functions(FunctionTable& t) {
  add(t, "xrCreateActionSet", &create_action_set);
  add(t, "xrDestroyActionSet", &destroy_action_set);
  add(t, "xrCreateAction", &create_action);
  add(t, "xrDestroyAction", &destroy_action);
  add(t, "xrSuggestInteractionProfileBindings", &suggest_bindings);
  add(t, "xrAttachSessionActionSets", &attach_action_sets);
  add(t, "xrGetCurrentInteractionProfile", &get_current_interaction_profile);
  add(t, "xrSyncActions", &sync_actions);
  add(t, "xrGetActionStateBoolean", &get_state_boolean);
  add(t, "xrGetActionStateFloat", &get_state_float);
  add(t, "xrGetActionStateVector2f", &get_state_vector2f);
  add(t, "xrGetActionStatePose", &get_state_pose);
  add(t, "xrEnumerateBoundSourcesForAction", &enumerate_bound_sources);
  add(t, "xrGetInputSourceLocalizedName", &get_input_source_localized_name);
  add(t, "xrApplyHapticFeedback", &apply_haptic);
  add(t, "xrStopHapticFeedback", &stop_haptic);
}

}  // namespace foveart::sim
