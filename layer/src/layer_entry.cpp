// Loader negotiation, instance creation and xrGetInstanceProcAddr: the only
// way into the layer. xrNegotiateLoaderApiLayerInterface is the single
// exported symbol (visibility + exports.map).
#include <cstring>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "barrier.hpp"
#include "eye_gaze.hpp"
#include "hooks.hpp"
#include "loader_interfaces.h"
#include "log.hpp"
#include "state.hpp"

namespace foveart::layer {
namespace {

constexpr std::string_view kLayerName = XR_FOVEART_API_LAYER_NAME;

bool has_extension(const XrInstanceCreateInfo* info, const char* name) {
  for (uint32_t i = 0; i < info->enabledExtensionCount; ++i) {
    if (info->enabledExtensionNames[i] != nullptr && std::strcmp(info->enabledExtensionNames[i], name) == 0) {
      return true;
    }
  }
  return false;
}

// The loader's create info is the version this layer was built for, and its next link is for this layer.
bool loader_info_valid(const XrApiLayerCreateInfo* layer_info) {
  if (layer_info->structType != XR_LOADER_INTERFACE_STRUCT_API_LAYER_CREATE_INFO ||
      layer_info->structVersion != FOVEART_API_LAYER_CREATE_INFO_STRUCT_VERSION ||
      layer_info->structSize != sizeof(XrApiLayerCreateInfo)) {
    log(LogLevel::Error, "xrCreateApiLayerInstance: unexpected XrApiLayerCreateInfo (type ",
        static_cast<int>(layer_info->structType), ", version ", layer_info->structVersion, ", size ",
        layer_info->structSize, ")");
    return false;
  }
  const XrApiLayerNextInfo* next_info = layer_info->nextInfo;
  if (next_info == nullptr || next_info->structType != XR_LOADER_INTERFACE_STRUCT_API_LAYER_NEXT_INFO ||
      next_info->structVersion != FOVEART_API_LAYER_NEXT_INFO_STRUCT_VERSION ||
      next_info->structSize != sizeof(XrApiLayerNextInfo) ||
      std::string_view(next_info->layerName,
                       strnlen(next_info->layerName, XR_MAX_API_LAYER_NAME_SIZE)) != kLayerName ||
      next_info->nextGetInstanceProcAddr == nullptr || next_info->nextCreateApiLayerInstance == nullptr) {
    log(LogLevel::Error, "xrCreateApiLayerInstance: the loader's XrApiLayerNextInfo is not for ", kLayerName);
    return false;
  }
  return true;
}

// The instance's state before it exists: the app's config (logged) and the extensions it enabled.
std::shared_ptr<InstanceState> new_instance_state(const XrInstanceCreateInfo* info) {
  const std::string app_name(info->applicationInfo.applicationName,
                             strnlen(info->applicationInfo.applicationName, XR_MAX_APPLICATION_NAME_SIZE));
  auto config = load_config(app_name, process_env());
  log_configure(config.config.log_level, config.config.log_file);
  for (const auto& w : config.warnings) log(LogLevel::Warn, w);
  log(LogLevel::Info, "xrCreateInstance for '", app_name, "', config ",
      config.path.empty() ? std::string("(none: defaults)") : config.path,
      config.config.enabled ? "" : "; layer disabled");

  auto state = std::make_shared<InstanceState>();
  state->config = config.config;
  state->application_name = app_name;
  state->extension_enabled = has_extension(info, XR_FOVEART_FOVEATED_RAY_TRACING_EXTENSION_NAME);
  state->vulkan2_enabled = has_extension(info, XR_KHR_VULKAN_ENABLE2_EXTENSION_NAME);
  state->eye_gaze_enabled = has_extension(info, XR_EXT_EYE_GAZE_INTERACTION_EXTENSION_NAME);
  return state;
}

// What the layers below and the runtime are asked to enable.
struct DownRequest {
  std::vector<const char*> extensions;
  std::vector<const char*> layers;
  bool added_eye_gaze = false;       // XR_EXT_eye_gaze_interaction added for the layer, hidden from the app
  bool eye_gaze_unanswered = false;  // the next link's extension list could not be enumerated
};

DownRequest down_request(const XrInstanceCreateInfo* info, const XrApiLayerNextInfo* next_info, InstanceState& state) {
  DownRequest down;
  // Our extension is implemented here: the layers below and the runtime never see it.
  for (uint32_t i = 0; i < info->enabledExtensionCount; ++i) {
    const char* name = info->enabledExtensionNames[i];
    if (name != nullptr && std::strcmp(name, XR_FOVEART_FOVEATED_RAY_TRACING_EXTENSION_NAME) == 0) continue;
    down.extensions.push_back(name);
  }
  // Nor our layer name: what is below us never learns about us.
  for (uint32_t i = 0; i < info->enabledApiLayerCount; ++i) {
    const char* name = info->enabledApiLayerNames[i];
    if (name != nullptr && kLayerName == name) continue;
    down.layers.push_back(name);
  }
  // XR_EXT_eye_gaze_interaction for the layer's gaze source: enabled below us
  // when the app enabled our extension and the next link offers it, even if the
  // app did not ask for it (then it is hidden from the app).
  if (state.extension_enabled && state.config.enabled && !state.eye_gaze_enabled) {
    bool answered = false;
    const bool offered = next_offers_extension(next_info->nextGetInstanceProcAddr,
                                               XR_EXT_EYE_GAZE_INTERACTION_EXTENSION_NAME, &answered);
    down.eye_gaze_unanswered = !answered;
    if (offered || !answered) {  // unanswered: try, and retry without it if refused
      down.extensions.push_back(XR_EXT_EYE_GAZE_INTERACTION_EXTENSION_NAME);
      down.added_eye_gaze = true;
    } else {
      state.eye_gaze.unavailable_reason = "the runtime (or the next layer) does not offer it";
      log(LogLevel::Info, "XR_EXT_eye_gaze_interaction: not offered by the runtime (or the next layer); "
                          "gaze source eye_gaze_interaction will use fixed foveation");
    }
  }
  return down;
}

// Creates the instance below the layer; without the eye-gaze extension it added, if that is refused.
XrResult create_below(const XrInstanceCreateInfo* info, const XrApiLayerCreateInfo* layer_info, DownRequest& down,
                      InstanceState& state, XrInstance* out_instance) {
  const XrApiLayerNextInfo* next_info = layer_info->nextInfo;
  XrInstanceCreateInfo down_info = *info;
  down_info.enabledApiLayerCount = static_cast<uint32_t>(down.layers.size());
  down_info.enabledApiLayerNames = down.layers.empty() ? nullptr : down.layers.data();
  down_info.enabledExtensionCount = static_cast<uint32_t>(down.extensions.size());
  down_info.enabledExtensionNames = down.extensions.empty() ? nullptr : down.extensions.data();

  XrApiLayerCreateInfo down_layer_info = *layer_info;
  down_layer_info.nextInfo = next_info->next;
  XrResult result = next_info->nextCreateApiLayerInstance(&down_info, &down_layer_info, out_instance);
  if (result == XR_ERROR_EXTENSION_NOT_PRESENT && down.added_eye_gaze) {
    down.extensions.pop_back();
    down.added_eye_gaze = false;
    down_info.enabledExtensionCount = static_cast<uint32_t>(down.extensions.size());
    down_info.enabledExtensionNames = down.extensions.empty() ? nullptr : down.extensions.data();
    state.eye_gaze.unavailable_reason = "the runtime (or the next layer) refused it";
    log(LogLevel::Info, "XR_EXT_eye_gaze_interaction: refused below the layer",
        down.eye_gaze_unanswered ? " (the extension list could not be enumerated)" : "",
        "; gaze source eye_gaze_interaction will use fixed foveation");
    result = next_info->nextCreateApiLayerInstance(&down_info, &down_layer_info, out_instance);
  }
  return result;
}

XrResult create_api_layer_instance(const XrInstanceCreateInfo* info, const XrApiLayerCreateInfo* layer_info,
                                   XrInstance* out_instance) {
  if (info == nullptr || layer_info == nullptr || out_instance == nullptr) return XR_ERROR_VALIDATION_FAILURE;
  if (!loader_info_valid(layer_info)) return XR_ERROR_INITIALIZATION_FAILED;
  const XrApiLayerNextInfo* next_info = layer_info->nextInfo;
  auto state = new_instance_state(info);
  DownRequest down = down_request(info, next_info, *state);
  const XrResult result = create_below(info, layer_info, down, *state, out_instance);
  if (XR_FAILED(result)) return result;

  state->handle = *out_instance;
  if (!load_next_dispatch(state->handle, next_info->nextGetInstanceProcAddr, &state->next)) {
    log(LogLevel::Error, "xrCreateInstance: the next layer/runtime lacks core functions");
    if (state->next.DestroyInstance != nullptr) state->next.DestroyInstance(state->handle);
    *out_instance = XR_NULL_HANDLE;
    return XR_ERROR_INITIALIZATION_FAILED;
  }
  state->eye_gaze.extension_enabled = state->eye_gaze_enabled || down.added_eye_gaze;
  state->eye_gaze.hidden_from_app = down.added_eye_gaze;
  if (state->extension_enabled && state->config.enabled && state->eye_gaze.extension_enabled) {
    create_eye_gaze_actions(state->handle, next_info->nextGetInstanceProcAddr, &state->eye_gaze);
  }
  Registry::get().add_instance(std::move(state));
  return result;
}

XRAPI_ATTR XrResult XRAPI_CALL hook_xrCreateApiLayerInstance(const XrInstanceCreateInfo* info,
                                                               const XrApiLayerCreateInfo* layer_info,
                                                               XrInstance* out_instance) noexcept {
  return exception_barrier("xrCreateApiLayerInstance",
                           [&] { return create_api_layer_instance(info, layer_info, out_instance); });
}

XRAPI_ATTR XrResult XRAPI_CALL hook_xrGetInstanceProcAddr(XrInstance instance, const char* name,
                                                            PFN_xrVoidFunction* function) noexcept {
  return exception_barrier("xrGetInstanceProcAddr", [&]() -> XrResult {
    if (name == nullptr || function == nullptr) return XR_ERROR_VALIDATION_FAILURE;
    *function = nullptr;
    const std::string_view fn(name);
    if (fn == "xrGetInstanceProcAddr") {
      *function = reinterpret_cast<PFN_xrVoidFunction>(&hook_xrGetInstanceProcAddr);
      return XR_SUCCESS;
    }
    auto state = Registry::get().instance(instance);
    if (state == nullptr) return XR_ERROR_HANDLE_INVALID;
    if (state->config.enabled) {
      if (PFN_xrVoidFunction hook = find_hook(fn, *state)) {
        *function = hook;
        return XR_SUCCESS;
      }
      if (is_extension_function(fn)) return XR_ERROR_FUNCTION_UNSUPPORTED;  // not enabled
    } else if (is_extension_function(fn)) {
      return XR_ERROR_FUNCTION_UNSUPPORTED;
    } else if (fn == "xrDestroyInstance") {
      // Even disabled, the layer forgets the instance at destruction.
      *function = find_hook(fn, *state);
      return XR_SUCCESS;
    }
    return state->next.GetInstanceProcAddr(instance, name, function);
  });
}

}  // namespace

XrResult negotiate(const XrNegotiateLoaderInfo* loader_info, const char* layer_name,
                   XrNegotiateApiLayerRequest* request) {
  if (loader_info == nullptr || request == nullptr) return XR_ERROR_INITIALIZATION_FAILED;
  if (loader_info->structType != XR_LOADER_INTERFACE_STRUCT_LOADER_INFO ||
      loader_info->structVersion != FOVEART_LOADER_INFO_STRUCT_VERSION ||
      loader_info->structSize != sizeof(XrNegotiateLoaderInfo)) {
    log(LogLevel::Error, "negotiation: unexpected XrNegotiateLoaderInfo");
    return XR_ERROR_INITIALIZATION_FAILED;
  }
  if (request->structType != XR_LOADER_INTERFACE_STRUCT_API_LAYER_REQUEST ||
      request->structVersion != FOVEART_API_LAYER_INFO_STRUCT_VERSION ||
      request->structSize != sizeof(XrNegotiateApiLayerRequest)) {
    log(LogLevel::Error, "negotiation: unexpected XrNegotiateApiLayerRequest");
    return XR_ERROR_INITIALIZATION_FAILED;
  }
  if (layer_name == nullptr || std::string_view(layer_name) != kLayerName) {
    log(LogLevel::Error, "negotiation: asked for layer '", layer_name ? layer_name : "(null)", "', this is ",
        kLayerName);
    return XR_ERROR_INITIALIZATION_FAILED;
  }
  if (loader_info->minInterfaceVersion > FOVEART_LOADER_API_LAYER_INTERFACE_VERSION ||
      loader_info->maxInterfaceVersion < FOVEART_LOADER_API_LAYER_INTERFACE_VERSION ||
      loader_info->minApiVersion > XR_CURRENT_API_VERSION ||
      loader_info->maxApiVersion < XR_MAKE_VERSION(1, 0, 0)) {
    log(LogLevel::Error, "negotiation: loader interface/API versions do not overlap with the layer's");
    return XR_ERROR_INITIALIZATION_FAILED;
  }
  request->layerInterfaceVersion = FOVEART_LOADER_API_LAYER_INTERFACE_VERSION;
  request->layerApiVersion = XR_CURRENT_API_VERSION;
  request->getInstanceProcAddr = &hook_xrGetInstanceProcAddr;
  request->createApiLayerInstance = &hook_xrCreateApiLayerInstance;
  return XR_SUCCESS;
}

}  // namespace foveart::layer

extern "C" __attribute__((visibility("default"))) XRAPI_ATTR XrResult XRAPI_CALL
xrNegotiateLoaderApiLayerInterface(const XrNegotiateLoaderInfo* loader_info, const char* layer_name,
                                   XrNegotiateApiLayerRequest* request) noexcept {
  return foveart::layer::exception_barrier(
      "xrNegotiateLoaderApiLayerInterface",
      [&] { return foveart::layer::negotiate(loader_info, layer_name, request); });
}
