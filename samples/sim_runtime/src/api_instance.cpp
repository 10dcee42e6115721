// Instance, system, view configuration, paths, events and time conversion.
#include <openxr/openxr_reflection.h>

#include <cstring>

#include "api_common.h"
#include "icd_pin.h"
#include "sim_runtime/sim_env.h"

namespace foveart::sim {
namespace {

struct ExtensionInfo {
  const char* name;
  uint32_t version;
};
constexpr ExtensionInfo kExtensions[] = {
    {XR_KHR_VULKAN_ENABLE2_EXTENSION_NAME, XR_KHR_vulkan_enable2_SPEC_VERSION},
    {XR_KHR_VULKAN_ENABLE_EXTENSION_NAME, XR_KHR_vulkan_enable_SPEC_VERSION},
    {XR_EXT_EYE_GAZE_INTERACTION_EXTENSION_NAME, XR_EXT_eye_gaze_interaction_SPEC_VERSION},
    {XR_KHR_CONVERT_TIMESPEC_TIME_EXTENSION_NAME, XR_KHR_convert_timespec_time_SPEC_VERSION},
};

XRAPI_ATTR XrResult XRAPI_CALL enumerate_instance_extension_properties(
    const char* layerName, uint32_t capacity, uint32_t* count, XrExtensionProperties* props) {
  return guarded("xrEnumerateInstanceExtensionProperties", [&]() -> XrResult {
    if (layerName != nullptr && layerName[0] != '\0') return XR_ERROR_API_LAYER_NOT_PRESENT;
    if (count == nullptr) return XR_ERROR_VALIDATION_FAILURE;
    const uint32_t n = static_cast<uint32_t>(std::size(kExtensions));
    *count = n;
    if (capacity == 0) return XR_SUCCESS;
    if (capacity < n) return XR_ERROR_SIZE_INSUFFICIENT;
    if (props == nullptr) return XR_ERROR_VALIDATION_FAILURE;
    for (uint32_t i = 0; i < n; ++i) {
      if (props[i].type != XR_TYPE_EXTENSION_PROPERTIES) return XR_ERROR_VALIDATION_FAILURE;
      std::strncpy(props[i].extensionName, kExtensions[i].name, XR_MAX_EXTENSION_NAME_SIZE - 1);
      props[i].extensionName[XR_MAX_EXTENSION_NAME_SIZE - 1] = '\0';
      props[i].extensionVersion = kExtensions[i].version;
    }
    return XR_SUCCESS;
  });
}

XRAPI_ATTR XrResult XRAPI_CALL enumerate_api_layer_properties(uint32_t, uint32_t* count,
                                                              XrApiLayerProperties*) {
  if (count == nullptr) return XR_ERROR_VALIDATION_FAILURE;
  *count = 0;
  return XR_SUCCESS;
}

// Records the extensions the app enabled; any this runtime lacks fails.
XrResult enable_extensions(const XrInstanceCreateInfo* info, Instance& inst) {
  for (uint32_t i = 0; i < info->enabledExtensionCount; ++i) {
    const char* e = info->enabledExtensionNames[i];
    if (e == nullptr) return XR_ERROR_VALIDATION_FAILURE;
    if (std::strcmp(e, XR_KHR_VULKAN_ENABLE2_EXTENSION_NAME) == 0)
      inst.ext_vulkan2 = true;
    else if (std::strcmp(e, XR_KHR_VULKAN_ENABLE_EXTENSION_NAME) == 0)
      inst.ext_vulkan = true;
    else if (std::strcmp(e, XR_EXT_EYE_GAZE_INTERACTION_EXTENSION_NAME) == 0)
      inst.ext_eye_gaze = true;
    else if (std::strcmp(e, XR_KHR_CONVERT_TIMESPEC_TIME_EXTENSION_NAME) == 0)
      inst.ext_timespec = true;
    else
      return XR_ERROR_EXTENSION_NOT_PRESENT;
  }
  return XR_SUCCESS;
}

// Head and gaze: a scripted motion drives both; else a gaze trace file or the built-in saccade script.
XrResult set_up_motion_and_gaze(const Config& config, Instance& inst) {
  std::string error;
  if (!config.motion.empty()) {
    // The motion drives head and gaze: FOVEART_SIM_HEAD and FOVEART_SIM_GAZE step aside.
    auto motion = MotionSource::from_spec(config.motion, config.motion_seed, &error);
    if (!motion) {
      log(LogLevel::Error, std::string(env::kMotion) + ": " + error);
      return XR_ERROR_RUNTIME_FAILURE;
    }
    if (!config.gaze_file.empty()) {
      log(LogLevel::Info, std::string(env::kMotion) + " drives the gaze: " + env::kGaze + " ignored");
    }
    if (config.head_sway) {
      log(LogLevel::Info, std::string(env::kMotion) + " drives the head: " + env::kHead + " ignored");
    }
    inst.motion = std::move(*motion);
    inst.gaze = GazeSource::saccade_script();
  } else if (!config.gaze_file.empty()) {
    auto gaze = GazeSource::from_trace_file(config.gaze_file, &error);
    if (!gaze) {
      log(LogLevel::Error, std::string(env::kGaze) + ": " + error);
      return XR_ERROR_INITIALIZATION_FAILED;
    }
    if (gaze->skipped_rows() > 0) {
      log(LogLevel::Info, std::string(env::kGaze) + ": skipped " + std::to_string(gaze->skipped_rows()) +
                              " rows whose device time does not increase");
    }
    inst.gaze = std::move(*gaze);
  } else {
    inst.gaze = GazeSource::saccade_script();
  }
  return XR_SUCCESS;
}

void log_instance_created(const Instance& inst) {
  const Config& config = inst.config;
  log(LogLevel::Info,
      "instance for '" + inst.application_name + "': clock " + (config.virtual_clock ? "virtual" : "real") +
          ", frame budget " + (config.frame_budget ? std::to_string(config.frame_budget) : std::string("none")) +
          (inst.motion ? ", head and gaze from the motion " + inst.motion->name()
                       : std::string(", head ") + (config.head_sway ? "sway" : "static") + ", gaze " +
                             (config.gaze_file.empty() ? "built-in saccade script" : config.gaze_file)) +
          (config.eye_tracking ? "" : " (eye tracking off)") +
          (config.capture_dir.empty() ? "" : ", capture to " + config.capture_dir));
}

XRAPI_ATTR XrResult XRAPI_CALL create_instance(const XrInstanceCreateInfo* info, XrInstance* out) {
  return guarded("xrCreateInstance", [&]() -> XrResult {
    FOVEART_CHECK_STRUCT(info, XR_TYPE_INSTANCE_CREATE_INFO);
    if (out == nullptr) return XR_ERROR_VALIDATION_FAILURE;
    if (XR_VERSION_MAJOR(info->applicationInfo.apiVersion) != 1)
      return XR_ERROR_API_VERSION_UNSUPPORTED;
    if (info->applicationInfo.applicationName[0] == '\0') return XR_ERROR_NAME_INVALID;
    if (info->enabledApiLayerCount > 0) return XR_ERROR_API_LAYER_NOT_PRESENT;
    Runtime& rt = runtime();
    std::lock_guard<std::mutex> lock(rt.mutex);
    if (rt.instance) return XR_ERROR_LIMIT_REACHED;  // one instance per process, like the loader
    auto inst = std::make_unique<Instance>();
    if (const XrResult r = enable_extensions(info, *inst); XR_FAILED(r)) return r;
    std::string error;
    auto config = config_from_environment(&error);
    if (!config) {
      log(LogLevel::Error, error);
      return XR_ERROR_INITIALIZATION_FAILED;
    }
    set_log_level(config->log_level);
    inst->config = *config;
    inst->clock = SimClock(config->virtual_clock);
    inst->origin_ns = inst->clock.now_ns();
    if (const XrResult r = set_up_motion_and_gaze(inst->config, *inst); XR_FAILED(r)) return r;
    inst->application_name = info->applicationInfo.applicationName;
    inst->id = rt.next_id++;
    *out = to_handle<XrInstance>(inst->id);
    log_instance_created(*inst);
    rt.instance = std::move(inst);
    return XR_SUCCESS;
  });
}

XRAPI_ATTR XrResult XRAPI_CALL destroy_instance(XrInstance instance) {
  return guarded("xrDestroyInstance", [&]() -> XrResult {
    FOVEART_LOCK_INSTANCE(instance);
    (void)inst;
    std::vector<uint64_t> ids;
    for (auto& [id, s] : rt.sessions) ids.push_back(id);
    for (uint64_t id : ids) destroy_session_children(rt, id);
    rt.sessions.clear();
    rt.actions.clear();
    rt.action_sets.clear();
    rt.instance.reset();
    rt.frame_order_changed.notify_all();  // a blocked xrWaitFrame returns HANDLE_INVALID
    pin_loaded_vulkan_icds_and_layers();  // the loaders unload layers next (icd_pin.h)
    return XR_SUCCESS;
  });
}

XRAPI_ATTR XrResult XRAPI_CALL get_instance_properties(XrInstance instance,
                                                       XrInstanceProperties* props) {
  return guarded("xrGetInstanceProperties", [&]() -> XrResult {
    FOVEART_LOCK_INSTANCE(instance);
    (void)inst;
    FOVEART_CHECK_STRUCT(props, XR_TYPE_INSTANCE_PROPERTIES);
    props->runtimeVersion = XR_MAKE_VERSION(0, 1, 0);
    std::snprintf(props->runtimeName, XR_MAX_RUNTIME_NAME_SIZE, "FoveaRT simulated FOVE 0");
    return XR_SUCCESS;
  });
}

XRAPI_ATTR XrResult XRAPI_CALL poll_event(XrInstance instance, XrEventDataBuffer* event) {
  return guarded("xrPollEvent", [&]() -> XrResult {
    FOVEART_LOCK_INSTANCE(instance);
    if (event == nullptr) return XR_ERROR_VALIDATION_FAILURE;
    if (inst->events.empty()) return XR_EVENT_UNAVAILABLE;
    *event = inst->events.front();
    inst->events.pop_front();
    return XR_SUCCESS;
  });
}

XRAPI_ATTR XrResult XRAPI_CALL result_to_string(XrInstance instance, XrResult value,
                                                char buffer[XR_MAX_RESULT_STRING_SIZE]) {
  return guarded("xrResultToString", [&]() -> XrResult {
    FOVEART_LOCK_INSTANCE(instance);
    (void)inst;
    if (buffer == nullptr) return XR_ERROR_VALIDATION_FAILURE;
    const char* name = nullptr;
    switch (value) {
#define FOVEART_RESULT_CASE(n, v) \
  case n:                         \
    name = #n;                    \
    break;
      XR_LIST_ENUM_XrResult(FOVEART_RESULT_CASE)
#undef FOVEART_RESULT_CASE
          default : break;
    }
    // OpenXR 1.0, xrResultToString: unknown codes read XR_UNKNOWN_SUCCESS_<value> or
    // XR_UNKNOWN_FAILURE_<value>, the value as a signed decimal (a failure keeps its '-').
    if (name != nullptr)
      std::snprintf(buffer, XR_MAX_RESULT_STRING_SIZE, "%s", name);
    else
      std::snprintf(buffer, XR_MAX_RESULT_STRING_SIZE, "XR_UNKNOWN_%s_%d", value >= 0 ? "SUCCESS" : "FAILURE",
                    static_cast<int>(value));
    return XR_SUCCESS;
  });
}

XRAPI_ATTR XrResult XRAPI_CALL structure_type_to_string(XrInstance instance, XrStructureType value,
                                                        char buffer[XR_MAX_STRUCTURE_NAME_SIZE]) {
  return guarded("xrStructureTypeToString", [&]() -> XrResult {
    FOVEART_LOCK_INSTANCE(instance);
    (void)inst;
    if (buffer == nullptr) return XR_ERROR_VALIDATION_FAILURE;
    const char* name = nullptr;
    switch (value) {
#define FOVEART_TYPE_CASE(n, v) \
  case n:                       \
    name = #n;                  \
    break;
      XR_LIST_ENUM_XrStructureType(FOVEART_TYPE_CASE)
#undef FOVEART_TYPE_CASE
          default : break;
    }
    if (name != nullptr)
      std::snprintf(buffer, XR_MAX_STRUCTURE_NAME_SIZE, "%s", name);
    else
      std::snprintf(buffer, XR_MAX_STRUCTURE_NAME_SIZE, "XR_UNKNOWN_STRUCTURE_TYPE_%d",
                    static_cast<int>(value));
    return XR_SUCCESS;
  });
}

XRAPI_ATTR XrResult XRAPI_CALL get_system(XrInstance instance, const XrSystemGetInfo* info,
                                          XrSystemId* out) {
  return guarded("xrGetSystem", [&]() -> XrResult {
    FOVEART_LOCK_INSTANCE(instance);
    (void)inst;
    FOVEART_CHECK_STRUCT(info, XR_TYPE_SYSTEM_GET_INFO);
    if (out == nullptr) return XR_ERROR_VALIDATION_FAILURE;
    // OpenXR 1.0, xrGetSystem: a form factor the runtime does not offer -- a handheld display,
    // or any value outside the enum -- is XR_ERROR_FORM_FACTOR_UNSUPPORTED.
    if (info->formFactor != XR_FORM_FACTOR_HEAD_MOUNTED_DISPLAY) return XR_ERROR_FORM_FACTOR_UNSUPPORTED;
    *out = kSystemId;
    return XR_SUCCESS;
  });
}

XRAPI_ATTR XrResult XRAPI_CALL get_system_properties(XrInstance instance, XrSystemId system,
                                                     XrSystemProperties* props) {
  return guarded("xrGetSystemProperties", [&]() -> XrResult {
    FOVEART_LOCK_INSTANCE(instance);
    if (system != kSystemId) return XR_ERROR_SYSTEM_INVALID;
    FOVEART_CHECK_STRUCT(props, XR_TYPE_SYSTEM_PROPERTIES);
    props->systemId = kSystemId;
    props->vendorId = 0x2C4B;  // arbitrary, stable
    std::snprintf(props->systemName, XR_MAX_SYSTEM_NAME_SIZE, "FOVE 0 (simulated)");
    props->graphicsProperties.maxSwapchainImageWidth = 4096;
    props->graphicsProperties.maxSwapchainImageHeight = 4096;
    props->graphicsProperties.maxLayerCount = kMaxLayers;
    props->trackingProperties.orientationTracking = XR_TRUE;
    props->trackingProperties.positionTracking = XR_TRUE;
    if (auto* eye = find_in_chain<XrSystemEyeGazeInteractionPropertiesEXT>(
            props->next, XR_TYPE_SYSTEM_EYE_GAZE_INTERACTION_PROPERTIES_EXT)) {
      eye->supportsEyeGazeInteraction =
          (inst->ext_eye_gaze && inst->config.eye_tracking) ? XR_TRUE : XR_FALSE;
    }
    return XR_SUCCESS;
  });
}

XRAPI_ATTR XrResult XRAPI_CALL enumerate_environment_blend_modes(XrInstance instance,
                                                                 XrSystemId system,
                                                                 XrViewConfigurationType type,
                                                                 uint32_t capacity, uint32_t* count,
                                                                 XrEnvironmentBlendMode* modes) {
  return guarded("xrEnumerateEnvironmentBlendModes", [&]() -> XrResult {
    FOVEART_LOCK_INSTANCE(instance);
    (void)inst;
    if (system != kSystemId) return XR_ERROR_SYSTEM_INVALID;
    if (type != XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO)
      return XR_ERROR_VIEW_CONFIGURATION_TYPE_UNSUPPORTED;
    return two_call(capacity, count, modes,
                    std::vector<XrEnvironmentBlendMode>{XR_ENVIRONMENT_BLEND_MODE_OPAQUE});
  });
}

XRAPI_ATTR XrResult XRAPI_CALL enumerate_view_configurations(XrInstance instance, XrSystemId system,
                                                             uint32_t capacity, uint32_t* count,
                                                             XrViewConfigurationType* types) {
  return guarded("xrEnumerateViewConfigurations", [&]() -> XrResult {
    FOVEART_LOCK_INSTANCE(instance);
    (void)inst;
    if (system != kSystemId) return XR_ERROR_SYSTEM_INVALID;
    return two_call(
        capacity, count, types,
        std::vector<XrViewConfigurationType>{XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO});
  });
}

XRAPI_ATTR XrResult XRAPI_CALL get_view_configuration_properties(
    XrInstance instance, XrSystemId system, XrViewConfigurationType type,
    XrViewConfigurationProperties* props) {
  return guarded("xrGetViewConfigurationProperties", [&]() -> XrResult {
    FOVEART_LOCK_INSTANCE(instance);
    (void)inst;
    if (system != kSystemId) return XR_ERROR_SYSTEM_INVALID;
    if (type != XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO)
      return XR_ERROR_VIEW_CONFIGURATION_TYPE_UNSUPPORTED;
    FOVEART_CHECK_STRUCT(props, XR_TYPE_VIEW_CONFIGURATION_PROPERTIES);
    props->viewConfigurationType = type;
    props->fovMutable = XR_FALSE;
    return XR_SUCCESS;
  });
}

XRAPI_ATTR XrResult XRAPI_CALL enumerate_view_configuration_views(
    XrInstance instance, XrSystemId system, XrViewConfigurationType type, uint32_t capacity,
    uint32_t* count, XrViewConfigurationView* views) {
  return guarded("xrEnumerateViewConfigurationViews", [&]() -> XrResult {
    FOVEART_LOCK_INSTANCE(instance);
    (void)inst;
    if (system != kSystemId) return XR_ERROR_SYSTEM_INVALID;
    if (type != XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO)
      return XR_ERROR_VIEW_CONFIGURATION_TYPE_UNSUPPORTED;
    if (count == nullptr) return XR_ERROR_VALIDATION_FAILURE;
    *count = 2;
    if (capacity == 0) return XR_SUCCESS;
    if (capacity < 2) return XR_ERROR_SIZE_INSUFFICIENT;
    if (views == nullptr) return XR_ERROR_VALIDATION_FAILURE;
    for (uint32_t i = 0; i < 2; ++i) {
      if (views[i].type != XR_TYPE_VIEW_CONFIGURATION_VIEW) return XR_ERROR_VALIDATION_FAILURE;
      views[i].recommendedImageRectWidth = static_cast<uint32_t>(headset().eye_width_px);
      views[i].recommendedImageRectHeight = static_cast<uint32_t>(headset().eye_height_px);
      views[i].maxImageRectWidth = 4096;
      views[i].maxImageRectHeight = 4096;
      views[i].recommendedSwapchainSampleCount = 1;
      views[i].maxSwapchainSampleCount = 1;
    }
    return XR_SUCCESS;
  });
}

// OpenXR 1.0, section 6.1 "Well-Formed Path Strings": starts with '/', only [a-z0-9-_./],
// no empty component ('//'), no trailing '/', and no component made of periods alone
// ('.', '..', ...).
bool is_well_formed_path(const char* s) {
  const size_t n = strnlen(s, XR_MAX_PATH_LENGTH);
  if (n == 0 || n == XR_MAX_PATH_LENGTH || s[0] != '/' || s[n - 1] == '/') return false;
  bool component_all_periods = false;  // the component since the last '/' so far
  for (size_t i = 0; i < n; ++i) {
    const char c = s[i];
    const bool ok = (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '-' || c == '_' ||
                    c == '.' || c == '/';
    if (!ok) return false;
    if (c == '/') {
      if (i > 0 && component_all_periods) return false;
      if (i + 1 < n && s[i + 1] == '/') return false;
      component_all_periods = true;  // until a non-period shows up
    } else if (c != '.') {
      component_all_periods = false;
    }
  }
  return !component_all_periods;
}

XRAPI_ATTR XrResult XRAPI_CALL string_to_path(XrInstance instance, const char* s, XrPath* out) {
  return guarded("xrStringToPath", [&]() -> XrResult {
    FOVEART_LOCK_INSTANCE(instance);
    if (s == nullptr || out == nullptr) return XR_ERROR_VALIDATION_FAILURE;
    if (!is_well_formed_path(s)) return XR_ERROR_PATH_FORMAT_INVALID;
    *out = intern_path(*inst, s);
    return XR_SUCCESS;
  });
}

XRAPI_ATTR XrResult XRAPI_CALL path_to_string(XrInstance instance, XrPath path, uint32_t capacity,
                                              uint32_t* count, char* buffer) {
  return guarded("xrPathToString", [&]() -> XrResult {
    FOVEART_LOCK_INSTANCE(instance);
    const std::string* s = path_string(*inst, path);
    if (s == nullptr) return XR_ERROR_PATH_INVALID;
    return two_call_string(capacity, count, buffer, *s);
  });
}

XRAPI_ATTR XrResult XRAPI_CALL convert_timespec_to_time(XrInstance instance,
                                                        const struct timespec* ts, XrTime* out) {
  return guarded("xrConvertTimespecTimeToTimeKHR", [&]() -> XrResult {
    FOVEART_LOCK_INSTANCE(instance);
    if (ts == nullptr || out == nullptr) return XR_ERROR_VALIDATION_FAILURE;
    const int64_t monotonic_ns = static_cast<int64_t>(ts->tv_sec) * 1'000'000'000 + ts->tv_nsec;
    const int64_t time_ns = inst->clock.from_monotonic_ns(monotonic_ns);
    if (time_ns <= 0) return XR_ERROR_TIME_INVALID;
    *out = time_ns;
    return XR_SUCCESS;
  });
}

XRAPI_ATTR XrResult XRAPI_CALL convert_time_to_timespec(XrInstance instance, XrTime time,
                                                        struct timespec* ts) {
  return guarded("xrConvertTimeToTimespecTimeKHR", [&]() -> XrResult {
    FOVEART_LOCK_INSTANCE(instance);
    if (ts == nullptr) return XR_ERROR_VALIDATION_FAILURE;
    if (time <= 0) return XR_ERROR_TIME_INVALID;
    const int64_t monotonic_ns = inst->clock.to_monotonic_ns(time);
    if (monotonic_ns < 0) return XR_ERROR_TIME_INVALID;
    ts->tv_sec = static_cast<time_t>(monotonic_ns / 1'000'000'000);
    ts->tv_nsec = static_cast<long>(monotonic_ns % 1'000'000'000);
    return XR_SUCCESS;
  });
}

}  // namespace

void register_instance_functions(FunctionTable& t) {
  add(t, "xrEnumerateInstanceExtensionProperties", &enumerate_instance_extension_properties);
  add(t, "xrEnumerateApiLayerProperties", &enumerate_api_layer_properties);
  add(t, "xrCreateInstance", &create_instance);
  add(t, "xrDestroyInstance", &destroy_instance);
  add(t, "xrGetInstanceProperties", &get_instance_properties);
  add(t, "xrPollEvent", &poll_event);
  add(t, "xrResultToString", &result_to_string);
  add(t, "xrStructureTypeToString", &structure_type_to_string);
  add(t, "xrGetSystem", &get_system);
  add(t, "xrGetSystemProperties", &get_system_properties);
  add(t, "xrEnumerateEnvironmentBlendModes", &enumerate_environment_blend_modes);
  add(t, "xrEnumerateViewConfigurations", &enumerate_view_configurations);
  add(t, "xrGetViewConfigurationProperties", &get_view_configuration_properties);
  add(t, "xrEnumerateViewConfigurationViews", &enumerate_view_configuration_views);
  add(t, "xrStringToPath", &string_to_path);
  add(t, "xrPathToString", &path_to_string);
  add(t, "xrConvertTimespecTimeToTimeKHR", &convert_timespec_to_time, Extension::Timespec);
  add(t, "xrConvertTimeToTimespecTimeKHR", &convert_time_to_timespec, Extension::Timespec);
}

}  // namespace foveart::sim
