// Loader negotiation and xrGetInstanceProcAddr: the runtime's only exported
// symbol is xrNegotiateLoaderRuntimeInterface (visibility + version script).
#include <cstring>

#include "api_common.h"

namespace foveart::sim {

Runtime& runtime() {
  static Runtime rt;
  return rt;
}

Instance* find_instance(XrInstance h) {
  Runtime& rt = runtime();
  if (!rt.instance || h == XR_NULL_HANDLE || rt.instance->id != handle_id(h)) return nullptr;
  return rt.instance.get();
}

XrResult two_call_string(uint32_t capacity, uint32_t* count_out, char* out, const std::string& s) {
  if (count_out == nullptr) return XR_ERROR_VALIDATION_FAILURE;
  *count_out = static_cast<uint32_t>(s.size() + 1);
  if (capacity == 0) return XR_SUCCESS;
  if (capacity < s.size() + 1) return XR_ERROR_SIZE_INSUFFICIENT;
  if (out == nullptr) return XR_ERROR_VALIDATION_FAILURE;
  std::memcpy(out, s.c_str(), s.size() + 1);
  return XR_SUCCESS;
}

bool is_well_formed_name(const char* name, size_t max_size) {
  const size_t n = strnlen(name, max_size);
  if (n == 0 || n == max_size) return false;
  for (size_t i = 0; i < n; ++i) {
    const char c = name[i];
    if (!((c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '-' || c == '_' || c == '.'))
      return false;
  }
  return true;
}

namespace {

const FunctionTable& function_table() {
  static const FunctionTable table = [] {
    FunctionTable t;
    register_instance_functions(t);
    register_vulkan_functions(t);
    register_session_functions(t);
    register_space_functions(t);
    register_swapchain_functions(t);
    register_action_functions(t);
    return t;
  }();
  return table;
}

bool extension_enabled(const Instance& inst, Extension ext) {
  switch (ext) {
    case Extension::None:
      return true;
    case Extension::Vulkan:
      return inst.ext_vulkan;
    case Extension::Vulkan2:
      return inst.ext_vulkan2;
    case Extension::EyeGaze:
      return inst.ext_eye_gaze;
    case Extension::Timespec:
      return inst.ext_timespec;
  }
  return false;
}

XRAPI_ATTR XrResult XRAPI_CALL get_instance_proc_addr(XrInstance instance, const char* name,
                                                      PFN_xrVoidFunction* function) {
  return guarded("xrGetInstanceProcAddr", [&]() -> XrResult {
    if (name == nullptr || function == nullptr) return XR_ERROR_VALIDATION_FAILURE;
    *function = nullptr;
    if (std::strcmp(name, "xrGetInstanceProcAddr") == 0) {
      *function = reinterpret_cast<PFN_xrVoidFunction>(&get_instance_proc_addr);
      return XR_SUCCESS;
    }
    const auto& table = function_table();
    auto it = table.find(name);
    if (instance == XR_NULL_HANDLE) {
      // Only these may be fetched without an instance (spec 3.2).
      static const char* kGlobal[] = {"xrEnumerateInstanceExtensionProperties",
                                      "xrEnumerateApiLayerProperties", "xrCreateInstance"};
      for (const char* g : kGlobal) {
        if (std::strcmp(name, g) == 0 && it != table.end()) {
          *function = it->second.fn;
          return XR_SUCCESS;
        }
      }
      return XR_ERROR_HANDLE_INVALID;
    }
    Runtime& rt = runtime();
    std::lock_guard<std::mutex> lock(rt.mutex);
    Instance* inst = find_instance(instance);
    if (inst == nullptr) return XR_ERROR_HANDLE_INVALID;
    if (it == table.end() || !extension_enabled(*inst, it->second.extension))
      return XR_ERROR_FUNCTION_UNSUPPORTED;
    *function = it->second.fn;
    return XR_SUCCESS;
  });
}

}  // namespace

// Paths -------------------------------------------------------------------------

XrPath intern_path(Instance& inst, const std::string& s) {
  auto it = inst.path_ids.find(s);
  if (it != inst.path_ids.end()) return it->second;
  inst.path_strings.push_back(s);
  const XrPath id = inst.path_strings.size();
  inst.path_ids.emplace(s, id);
  return id;
}

const std::string* path_string(const Instance& inst, XrPath p) {
  if (p == XR_NULL_PATH || p > inst.path_strings.size()) return nullptr;
  return &inst.path_strings[p - 1];
}

}  // namespace foveart::sim

extern "C" __attribute__((visibility("default"))) XRAPI_ATTR XrResult XRAPI_CALL
xrNegotiateLoaderRuntimeInterface(const XrNegotiateLoaderInfo* loaderInfo,
                                  XrNegotiateRuntimeRequest* runtimeRequest) {
  using namespace foveart::sim;
  return guarded("xrNegotiateLoaderRuntimeInterface", [&]() -> XrResult {
    // Check type, version and size before trusting anything.
    if (loaderInfo == nullptr || runtimeRequest == nullptr ||
        loaderInfo->structType != XR_LOADER_INTERFACE_STRUCT_LOADER_INFO ||
        loaderInfo->structVersion != FOVEART_XR_LOADER_INFO_STRUCT_VERSION ||
        loaderInfo->structSize != sizeof(XrNegotiateLoaderInfo) ||
        runtimeRequest->structType != XR_LOADER_INTERFACE_STRUCT_RUNTIME_REQUEST ||
        runtimeRequest->structVersion != FOVEART_XR_RUNTIME_INFO_STRUCT_VERSION ||
        runtimeRequest->structSize != sizeof(XrNegotiateRuntimeRequest)) {
      log(LogLevel::Error, "loader negotiation: unexpected struct type/version/size");
      return XR_ERROR_INITIALIZATION_FAILED;
    }
    if (loaderInfo->minInterfaceVersion > FOVEART_XR_CURRENT_LOADER_RUNTIME_VERSION ||
        loaderInfo->maxInterfaceVersion < FOVEART_XR_CURRENT_LOADER_RUNTIME_VERSION ||
        XR_VERSION_MAJOR(loaderInfo->minApiVersion) > 1 ||
        XR_VERSION_MAJOR(loaderInfo->maxApiVersion) < 1) {
      log(LogLevel::Error, "loader negotiation: no common interface/API version");
      return XR_ERROR_INITIALIZATION_FAILED;
    }
    runtimeRequest->runtimeInterfaceVersion = FOVEART_XR_CURRENT_LOADER_RUNTIME_VERSION;
    runtimeRequest->runtimeApiVersion = XR_CURRENT_API_VERSION;
    runtimeRequest->getInstanceProcAddr = &get_instance_proc_addr;
    return XR_SUCCESS;
  });
}
