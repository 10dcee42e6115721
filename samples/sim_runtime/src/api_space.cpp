// Reference spaces (VIEW, LOCAL, STAGE), action spaces (eye gaze pose), the head
// (static, sway or the scripted motion), and xrLocateViews for the FOVE 0's two views.
#include <cmath>

#include "api_common.h"

namespace foveart::sim {
namespace {

XrSpaceLocationFlags all_valid_tracked() {
  return XR_SPACE_LOCATION_ORIENTATION_VALID_BIT | XR_SPACE_LOCATION_POSITION_VALID_BIT |
         XR_SPACE_LOCATION_ORIENTATION_TRACKED_BIT | XR_SPACE_LOCATION_POSITION_TRACKED_BIT;
}

// The scripted motion starts at the session's xrBeginSession (without a session: at
// xrCreateInstance, like gaze traces).
int64_t motion_origin_ns(const Instance& inst, const Session* session) {
  return session != nullptr ? session->motion_origin_ns : inst.origin_ns;
}

}  // namespace

XrFovf view_fov() {
  const foveation::EyeFovRad& fov = headset().eye_fov_rad;
  return XrFovf{static_cast<float>(fov.left), static_cast<float>(fov.right),
                static_cast<float>(fov.up), static_cast<float>(fov.down)};
}

Pose head_pose_in_local(const Instance& inst, const Session* session, int64_t time_ns) {
  if (inst.motion) return inst.motion->head_in_local(time_ns - motion_origin_ns(inst, session));
  Pose p;
  if (inst.config.head_sway) {
    const double t_s = static_cast<double>(time_ns - inst.origin_ns) * 1e-9;
    const double phase = 2.0 * M_PI * 0.1 * t_s;  // 0.1 Hz
    const float yaw = glm::radians(10.0F) * static_cast<float>(std::sin(phase));
    p.orientation = glm::angleAxis(yaw, glm::vec3(0.0F, 1.0F, 0.0F));
    p.position = glm::vec3(0.02F * static_cast<float>(std::sin(phase)), 0.0F, 0.0F);
  }
  return p;
}

GazeSample eye_tracker_sample(const Instance& inst, const Session* session, int64_t time_ns,
                              int64_t& sample_time_ns) {
  const int64_t origin_ns = inst.motion ? motion_origin_ns(inst, session) : inst.origin_ns;
  const GazeSample sample = inst.motion ? inst.motion->gaze_at(time_ns - origin_ns)
                                        : inst.gaze.sample_at(time_ns - origin_ns);
  sample_time_ns = origin_ns + sample.offset_ns;
  return sample;
}

bool space_pose_in_local(Runtime& rt, const Space& space, int64_t time_ns, Pose& out,
                         int64_t* gaze_sample_ns) {
  const Instance& inst = *rt.instance;
  if (space.kind == SpaceKind::Reference) {
    Pose base;
    switch (space.reference_type) {
      case XR_REFERENCE_SPACE_TYPE_VIEW:
        base = head_pose_in_local(inst, find(rt.sessions, space.session), time_ns);
        break;
      case XR_REFERENCE_SPACE_TYPE_STAGE:
        base.position = glm::vec3(0.0F, -kLocalAboveStageM, 0.0F);  // STAGE: the floor below LOCAL
        break;
      default:
        break;
    }
    out = base * space.offset;
    return true;
  }
  Action* action = find(rt.actions, space.action);
  const Session* session = find(rt.sessions, space.session);
  if (action == nullptr || session == nullptr || !action->bound_to_eye_gaze || !action->active ||
      !inst.config.eye_tracking || session->state != XR_SESSION_STATE_FOCUSED) {
    return false;
  }
  int64_t sample_time_ns = 0;
  const GazeSample sample = eye_tracker_sample(inst, session, time_ns, sample_time_ns);
  if (!sample.valid) return false;
  // The one place gaze leaves the runtime (xrLocateSpace of the eye gaze pose): the
  // traces' head space (+z forward) becomes OpenXR VIEW space (-z forward) here.
  const Pose gaze = head_pose_in_local(inst, session, time_ns) *
                    look_along(openxr_view_direction(sample.direction));
  out = gaze * space.offset;
  if (gaze_sample_ns != nullptr) *gaze_sample_ns = sample_time_ns;
  return true;
}

namespace {

bool is_supported_reference_space(XrReferenceSpaceType t) {
  return t == XR_REFERENCE_SPACE_TYPE_VIEW || t == XR_REFERENCE_SPACE_TYPE_LOCAL ||
         t == XR_REFERENCE_SPACE_TYPE_STAGE;
}

XRAPI_ATTR XrResult XRAPI_CALL enumerate_reference_spaces(XrSession handle, uint32_t capacity,
                                                          uint32_t* count,
                                                          XrReferenceSpaceType* out) {
  return guarded("xrEnumerateReferenceSpaces", [&]() -> XrResult {
    FOVEART_LOCK_SESSION(handle);
    (void)inst;
    (void)session;
    return two_call(capacity, count, out,
                    std::vector<XrReferenceSpaceType>{XR_REFERENCE_SPACE_TYPE_VIEW,
                                                      XR_REFERENCE_SPACE_TYPE_LOCAL,
                                                      XR_REFERENCE_SPACE_TYPE_STAGE});
  });
}

XRAPI_ATTR XrResult XRAPI_CALL create_reference_space(XrSession handle,
                                                      const XrReferenceSpaceCreateInfo* info,
                                                      XrSpace* out) {
  return guarded("xrCreateReferenceSpace", [&]() -> XrResult {
    FOVEART_LOCK_SESSION(handle);
    (void)inst;
    (void)session;
    FOVEART_CHECK_STRUCT(info, XR_TYPE_REFERENCE_SPACE_CREATE_INFO);
    if (out == nullptr) return XR_ERROR_VALIDATION_FAILURE;
    if (!is_supported_reference_space(info->referenceSpaceType))
      return XR_ERROR_REFERENCE_SPACE_UNSUPPORTED;
    if (!is_unit_quaternion(info->poseInReferenceSpace.orientation)) return XR_ERROR_POSE_INVALID;
    auto space = std::make_unique<Space>();
    space->id = rt.next_id++;
    space->session = handle;
    space->kind = SpaceKind::Reference;
    space->reference_type = info->referenceSpaceType;
    space->offset = from_xr(info->poseInReferenceSpace);
    *out = to_handle<XrSpace>(space->id);
    rt.spaces.emplace(space->id, std::move(space));
    return XR_SUCCESS;
  });
}

XRAPI_ATTR XrResult XRAPI_CALL get_reference_space_bounds_rect(XrSession handle,
                                                               XrReferenceSpaceType type,
                                                               XrExtent2Df* bounds) {
  return guarded("xrGetReferenceSpaceBoundsRect", [&]() -> XrResult {
    FOVEART_LOCK_SESSION(handle);
    (void)inst;
    (void)session;
    if (bounds == nullptr) return XR_ERROR_VALIDATION_FAILURE;
    if (!is_supported_reference_space(type)) return XR_ERROR_REFERENCE_SPACE_UNSUPPORTED;
    if (type == XR_REFERENCE_SPACE_TYPE_STAGE) {
      *bounds = {3.0F, 3.0F};
      return XR_SUCCESS;
    }
    *bounds = {0.0F, 0.0F};
    return XR_SPACE_BOUNDS_UNAVAILABLE;
  });
}

XRAPI_ATTR XrResult XRAPI_CALL create_action_space(XrSession handle,
                                                   const XrActionSpaceCreateInfo* info,
                                                   XrSpace* out) {
  return guarded("xrCreateActionSpace", [&]() -> XrResult {
    FOVEART_LOCK_SESSION(handle);
    (void)session;
    FOVEART_CHECK_STRUCT(info, XR_TYPE_ACTION_SPACE_CREATE_INFO);
    if (out == nullptr) return XR_ERROR_VALIDATION_FAILURE;
    Action* action = find(rt.actions, info->action);
    if (action == nullptr) return XR_ERROR_HANDLE_INVALID;
    if (action->type != XR_ACTION_TYPE_POSE_INPUT) return XR_ERROR_ACTION_TYPE_MISMATCH;
    if (info->subactionPath != XR_NULL_PATH) {
      if (path_string(*inst, info->subactionPath) == nullptr) return XR_ERROR_PATH_INVALID;
      bool declared = false;
      for (XrPath p : action->subaction_paths) declared |= (p == info->subactionPath);
      if (!declared) return XR_ERROR_PATH_UNSUPPORTED;
    }
    if (!is_unit_quaternion(info->poseInActionSpace.orientation)) return XR_ERROR_POSE_INVALID;
    auto space = std::make_unique<Space>();
    space->id = rt.next_id++;
    space->session = handle;
    space->kind = SpaceKind::Action;
    space->action = info->action;
    space->subaction_path = info->subactionPath;
    space->offset = from_xr(info->poseInActionSpace);
    *out = to_handle<XrSpace>(space->id);
    rt.spaces.emplace(space->id, std::move(space));
    return XR_SUCCESS;
  });
}

XRAPI_ATTR XrResult XRAPI_CALL destroy_space(XrSpace handle) {
  return guarded("xrDestroySpace", [&]() -> XrResult {
    Runtime& rt = runtime();
    std::lock_guard<std::mutex> lock(rt.mutex);
    if (find(rt.spaces, handle) == nullptr) return XR_ERROR_HANDLE_INVALID;
    rt.spaces.erase(handle_id(handle));
    return XR_SUCCESS;
  });
}

XRAPI_ATTR XrResult XRAPI_CALL locate_space(XrSpace space_handle, XrSpace base_handle, XrTime time,
                                            XrSpaceLocation* location) {
  return guarded("xrLocateSpace", [&]() -> XrResult {
    Runtime& rt = runtime();
    std::lock_guard<std::mutex> lock(rt.mutex);
    Space* space = find(rt.spaces, space_handle);
    Space* base = find(rt.spaces, base_handle);
    if (space == nullptr || base == nullptr || !rt.instance) return XR_ERROR_HANDLE_INVALID;
    if (space->session != base->session) return XR_ERROR_VALIDATION_FAILURE;
    FOVEART_CHECK_STRUCT(location, XR_TYPE_SPACE_LOCATION);
    if (time <= 0) return XR_ERROR_TIME_INVALID;
    Pose space_pose;
    Pose base_pose;
    int64_t sample_ns = 0;
    const bool located = space_pose_in_local(rt, *space, time, space_pose, &sample_ns) &&
                         space_pose_in_local(rt, *base, time, base_pose, nullptr);
    auto* sample_time =
        find_in_chain<XrEyeGazeSampleTimeEXT>(location->next, XR_TYPE_EYE_GAZE_SAMPLE_TIME_EXT);
    if (!located) {
      location->locationFlags = 0;
      location->pose = to_xr(Pose{});
      if (sample_time != nullptr) sample_time->time = 0;
      return XR_SUCCESS;
    }
    location->locationFlags = all_valid_tracked();
    location->pose = to_xr(inverse(base_pose) * space_pose);
    if (auto* velocity = find_in_chain<XrSpaceVelocity>(location->next, XR_TYPE_SPACE_VELOCITY)) {
      velocity->velocityFlags = 0;
    }
    if (sample_time != nullptr) sample_time->time = sample_ns;
    return XR_SUCCESS;
  });
}

XRAPI_ATTR XrResult XRAPI_CALL locate_views(XrSession handle, const XrViewLocateInfo* info,
                                            XrViewState* view_state, uint32_t capacity,
                                            uint32_t* count, XrView* views) {
  return guarded("xrLocateViews", [&]() -> XrResult {
    FOVEART_LOCK_SESSION(handle);
    (void)session;
    FOVEART_CHECK_STRUCT(info, XR_TYPE_VIEW_LOCATE_INFO);
    FOVEART_CHECK_STRUCT(view_state, XR_TYPE_VIEW_STATE);
    if (count == nullptr) return XR_ERROR_VALIDATION_FAILURE;
    if (info->viewConfigurationType != XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO) {
      return XR_ERROR_VIEW_CONFIGURATION_TYPE_UNSUPPORTED;
    }
    if (info->displayTime <= 0) return XR_ERROR_TIME_INVALID;
    Space* base = find(rt.spaces, info->space);
    if (base == nullptr || base->session != handle) return XR_ERROR_HANDLE_INVALID;
    *count = 2;
    if (capacity == 0) return XR_SUCCESS;
    if (capacity < 2) return XR_ERROR_SIZE_INSUFFICIENT;
    if (views == nullptr) return XR_ERROR_VALIDATION_FAILURE;
    for (uint32_t i = 0; i < 2; ++i) {
      if (views[i].type != XR_TYPE_VIEW) return XR_ERROR_VALIDATION_FAILURE;
    }
    Pose base_pose;
    if (!space_pose_in_local(rt, *base, info->displayTime, base_pose, nullptr)) {
      view_state->viewStateFlags = 0;
      return XR_SUCCESS;
    }
    const Pose head = head_pose_in_local(*inst, session, info->displayTime);
    for (uint32_t i = 0; i < 2; ++i) {
      Pose eye;
      eye.position = glm::vec3(static_cast<float>(headset().eye_offset_x_m(i)), 0.0F, 0.0F);
      views[i].pose = to_xr(inverse(base_pose) * head * eye);
      views[i].fov = view_fov();
    }
    view_state->viewStateFlags =
        XR_VIEW_STATE_ORIENTATION_VALID_BIT | XR_VIEW_STATE_POSITION_VALID_BIT |
        XR_VIEW_STATE_ORIENTATION_TRACKED_BIT | XR_VIEW_STATE_POSITION_TRACKED_BIT;
    return XR_SUCCESS;
  });
}

}  // namespace

void register_space_functions(FunctionTable& t) {
  add(t, "xrEnumerateReferenceSpaces", &enumerate_reference_spaces);
  add(t, "xrCreateReferenceSpace", &create_reference_space);
  add(t, "xrGetReferenceSpaceBoundsRect", &get_reference_space_bounds_rect);
  add(t, "xrCreateActionSpace", &create_action_space);
  add(t, "xrDestroySpace", &destroy_space);
  add(t, "xrLocateSpace", &locate_space);
  add(t, "xrLocateViews", &locate_views);
}

}  // namespace foveart::sim
