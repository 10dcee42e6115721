// XR_EXT_eye_gaze_interaction negotiated down the chain at xrCreateInstance,
// against a fake next link (runtime) that does or does not offer it: the
// layer enables it only when offered (or retries without it when the chain
// cannot be asked), hides it from an app that did not enable it, and merges
// its binding into the app's suggestions for the eye gaze profile.
#include <dlfcn.h>

#include <cstdint>
#include <cstdlib>
#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "layer/XR_FOVEART_foveated_ray_tracing.h"
#include "loader_interfaces.h"
#include "loader_structs.hpp"

namespace foveart::layer {
namespace {

struct FakeRuntime {
  bool offers_eye_gaze = true;
  bool enumerate_available = true;
  int create_calls = 0;
  std::vector<std::string> created_with;  // extensions of the successful create
  int action_sets_created = 0;
  int suggest_calls = 0;
  XrPath suggested_profile = XR_NULL_PATH;
  std::vector<XrActionSuggestedBinding> suggested;
  std::map<std::string, XrPath> paths;
};
FakeRuntime g_fake;

constexpr const char* kEyeGaze = XR_EXT_EYE_GAZE_INTERACTION_EXTENSION_NAME;
const XrInstance kFakeInstance = reinterpret_cast<XrInstance>(std::uintptr_t{0x4242});
const XrActionSet kFakeSet = reinterpret_cast<XrActionSet>(std::uintptr_t{0x51});
const XrAction kLayerAction = reinterpret_cast<XrAction>(std::uintptr_t{0x61});

XRAPI_ATTR XrResult XRAPI_CALL fake_enumerate(const char*, uint32_t capacity, uint32_t* count,
                                              XrExtensionProperties* props) {
  std::vector<const char*> names{XR_KHR_COMPOSITION_LAYER_DEPTH_EXTENSION_NAME};
  if (g_fake.offers_eye_gaze) names.push_back(kEyeGaze);
  *count = static_cast<uint32_t>(names.size());
  if (capacity == 0) return XR_SUCCESS;
  if (capacity < names.size()) return XR_ERROR_SIZE_INSUFFICIENT;
  for (std::size_t i = 0; i < names.size(); ++i) std::strncpy(props[i].extensionName, names[i], XR_MAX_EXTENSION_NAME_SIZE - 1);
  return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL fake_create(const XrInstanceCreateInfo* info, const XrApiLayerCreateInfo*,
                                           XrInstance* out) {
  ++g_fake.create_calls;
  std::vector<std::string> names;
  for (uint32_t i = 0; i < info->enabledExtensionCount; ++i) names.emplace_back(info->enabledExtensionNames[i]);
  for (const auto& n : names) {
    if (n == kEyeGaze && !g_fake.offers_eye_gaze) return XR_ERROR_EXTENSION_NOT_PRESENT;
  }
  g_fake.created_with = names;
  *out = kFakeInstance;
  return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL fake_destroy_instance(XrInstance) { return XR_SUCCESS; }
XRAPI_ATTR XrResult XRAPI_CALL fake_string_to_path(XrInstance, const char* s, XrPath* out) {
  auto [it, added] = g_fake.paths.emplace(s, g_fake.paths.size() + 1);
  *out = it->second;
  return XR_SUCCESS;
}
XRAPI_ATTR XrResult XRAPI_CALL fake_create_action_set(XrInstance, const XrActionSetCreateInfo*, XrActionSet* out) {
  ++g_fake.action_sets_created;
  *out = kFakeSet;
  return XR_SUCCESS;
}
XRAPI_ATTR XrResult XRAPI_CALL fake_destroy_action_set(XrActionSet) { return XR_SUCCESS; }
XRAPI_ATTR XrResult XRAPI_CALL fake_create_action(XrActionSet, const XrActionCreateInfo*, XrAction* out) {
  *out = kLayerAction;
  return XR_SUCCESS;
}
XRAPI_ATTR XrResult XRAPI_CALL fake_suggest(XrInstance, const XrInteractionProfileSuggestedBinding* info) {
  ++g_fake.suggest_calls;
  g_fake.suggested_profile = info->interactionProfile;
  g_fake.suggested.assign(info->suggestedBindings, info->suggestedBindings + info->countSuggestedBindings);
  return XR_SUCCESS;
}
// Everything else the layer loads but these tests never reach.
XRAPI_ATTR XrResult XRAPI_CALL fake_unused() { return XR_ERROR_FUNCTION_UNSUPPORTED; }

template <class Fn>
PFN_xrVoidFunction as_void(Fn fn) {
  return reinterpret_cast<PFN_xrVoidFunction>(fn);
}

XRAPI_ATTR XrResult XRAPI_CALL fake_gipa(XrInstance, const char* name, PFN_xrVoidFunction* fn) {
  const std::string n = name;
  *fn = nullptr;
  if (n == "xrEnumerateInstanceExtensionProperties") {
    if (!g_fake.enumerate_available) return XR_ERROR_FUNCTION_UNSUPPORTED;
    *fn = as_void(&fake_enumerate);
  } else if (n == "xrDestroyInstance") {
    *fn = as_void(&fake_destroy_instance);
  } else if (n == "xrStringToPath") {
    *fn = as_void(&fake_string_to_path);
  } else if (n == "xrCreateActionSet") {
    *fn = as_void(&fake_create_action_set);
  } else if (n == "xrDestroyActionSet") {
    *fn = as_void(&fake_destroy_action_set);
  } else if (n == "xrCreateAction") {
    *fn = as_void(&fake_create_action);
  } else if (n == "xrSuggestInteractionProfileBindings") {
    *fn = as_void(&fake_suggest);
  } else {
    *fn = as_void(&fake_unused);
  }
  return XR_SUCCESS;
}

class EyeGazeChain : public ::testing::Test {
 protected:
  void SetUp() override {
    g_fake = FakeRuntime{};
    config_ = std::filesystem::temp_directory_path() / ("foveart_eye_gaze_chain_" + std::to_string(::getpid()) + ".json");
    std::ofstream(config_) << R"({"log_level": "info"})";
    ::setenv("FOVEART_CONFIG", config_.c_str(), 1);
    ::unsetenv("FOVEART_DISABLE");
    handle_ = dlopen(FOVEART_LAYER_SO, RTLD_NOW | RTLD_LOCAL);
    ASSERT_NE(handle_, nullptr) << dlerror();
    auto negotiate = reinterpret_cast<PFN_xrNegotiateLoaderApiLayerInterface>(
        dlsym(handle_, "xrNegotiateLoaderApiLayerInterface"));
    ASSERT_NE(negotiate, nullptr);
    const XrNegotiateLoaderInfo loader = test::conforming_loader_info();
    request_ = test::empty_api_layer_request();
    ASSERT_EQ(negotiate(&loader, XR_FOVEART_API_LAYER_NAME, &request_), XR_SUCCESS);
  }
  void TearDown() override {
    if (instance_ != XR_NULL_HANDLE) {
      PFN_xrVoidFunction fn = nullptr;
      request_.getInstanceProcAddr(instance_, "xrDestroyInstance", &fn);
      if (fn != nullptr) reinterpret_cast<PFN_xrDestroyInstance>(fn)(instance_);
    }
    if (handle_ != nullptr) dlclose(handle_);
    ::unsetenv("FOVEART_CONFIG");
    std::filesystem::remove(config_);
  }

  // xrCreateInstance as the loader would call the layer; returns its log.
  std::string create(std::vector<const char*> app_extensions) {
    XrApiLayerNextInfo next{};
    next.structType = XR_LOADER_INTERFACE_STRUCT_API_LAYER_NEXT_INFO;
    next.structVersion = FOVEART_API_LAYER_NEXT_INFO_STRUCT_VERSION;
    next.structSize = sizeof(next);
    std::strcpy(next.layerName, XR_FOVEART_API_LAYER_NAME);
    next.nextGetInstanceProcAddr = &fake_gipa;
    next.nextCreateApiLayerInstance = &fake_create;
    XrApiLayerCreateInfo layer_info{};
    layer_info.structType = XR_LOADER_INTERFACE_STRUCT_API_LAYER_CREATE_INFO;
    layer_info.structVersion = FOVEART_API_LAYER_CREATE_INFO_STRUCT_VERSION;
    layer_info.structSize = sizeof(layer_info);
    layer_info.nextInfo = &next;
    XrInstanceCreateInfo info{};
    info.type = XR_TYPE_INSTANCE_CREATE_INFO;
    std::strcpy(info.applicationInfo.applicationName, "eye_gaze_chain_test");
    info.applicationInfo.apiVersion = XR_CURRENT_API_VERSION;
    info.enabledExtensionCount = static_cast<uint32_t>(app_extensions.size());
    info.enabledExtensionNames = app_extensions.data();
    ::testing::internal::CaptureStderr();
    result_ = request_.createApiLayerInstance(&info, &layer_info, &instance_);
    return ::testing::internal::GetCapturedStderr();
  }

  XrResult app_suggests_eye_gaze(XrAction app_action) {
    PFN_xrVoidFunction fn = nullptr;
    EXPECT_EQ(request_.getInstanceProcAddr(instance_, "xrSuggestInteractionProfileBindings", &fn), XR_SUCCESS);
    const XrActionSuggestedBinding binding{app_action, g_fake.paths.at("/user/eyes_ext/input/gaze_ext/pose")};
    XrInteractionProfileSuggestedBinding info{XR_TYPE_INTERACTION_PROFILE_SUGGESTED_BINDING, nullptr,
                                              g_fake.paths.at("/interaction_profiles/ext/eye_gaze_interaction"), 1,
                                              &binding};
    return reinterpret_cast<PFN_xrSuggestInteractionProfileBindings>(fn)(instance_, &info);
  }

  static bool has(const std::vector<std::string>& v, const char* s) {
    return std::find(v.begin(), v.end(), s) != v.end();
  }

  std::filesystem::path config_;
  void* handle_ = nullptr;
  XrNegotiateApiLayerRequest request_{};
  XrInstance instance_ = XR_NULL_HANDLE;
  XrResult result_ = XR_ERROR_RUNTIME_FAILURE;
};

TEST_F(EyeGazeChain, OfferedExtensionIsEnabledBelowAndHiddenFromTheApp) {
  const std::string log = create({XR_FOVEART_FOVEATED_RAY_TRACING_EXTENSION_NAME});
  ASSERT_EQ(result_, XR_SUCCESS) << log;
  EXPECT_TRUE(has(g_fake.created_with, kEyeGaze));
  EXPECT_FALSE(has(g_fake.created_with, XR_FOVEART_FOVEATED_RAY_TRACING_EXTENSION_NAME));
  // The layer's own action, suggested for the eye gaze profile.
  EXPECT_EQ(g_fake.action_sets_created, 1);
  ASSERT_EQ(g_fake.suggested.size(), 1u);
  EXPECT_EQ(g_fake.suggested[0].action, kLayerAction);
  EXPECT_NE(log.find("hidden from the app"), std::string::npos) << log;
  // To the app, which did not enable the extension, the profile does not exist.
  const int calls = g_fake.suggest_calls;
  EXPECT_EQ(app_suggests_eye_gaze(reinterpret_cast<XrAction>(std::uintptr_t{0x71})), XR_ERROR_PATH_UNSUPPORTED);
  EXPECT_EQ(g_fake.suggest_calls, calls);
}

TEST_F(EyeGazeChain, RuntimeWithoutTheExtensionIsLoggedAndLeftAlone) {
  g_fake.offers_eye_gaze = false;
  const std::string log = create({XR_FOVEART_FOVEATED_RAY_TRACING_EXTENSION_NAME});
  ASSERT_EQ(result_, XR_SUCCESS) << log;
  EXPECT_EQ(g_fake.create_calls, 1);
  EXPECT_FALSE(has(g_fake.created_with, kEyeGaze));
  EXPECT_EQ(g_fake.action_sets_created, 0);
  EXPECT_NE(log.find("XR_EXT_eye_gaze_interaction: not offered"), std::string::npos) << log;
}

TEST_F(EyeGazeChain, UnaskableChainIsTriedThenRetriedWithoutIt) {
  g_fake.offers_eye_gaze = false;
  g_fake.enumerate_available = false;
  const std::string log = create({XR_FOVEART_FOVEATED_RAY_TRACING_EXTENSION_NAME});
  ASSERT_EQ(result_, XR_SUCCESS) << log;
  EXPECT_EQ(g_fake.create_calls, 2);
  EXPECT_FALSE(has(g_fake.created_with, kEyeGaze));
  EXPECT_NE(log.find("refused below the layer"), std::string::npos) << log;
}

TEST_F(EyeGazeChain, AppsOwnSuggestionForTheProfileKeepsTheLayersBinding) {
  const std::string log = create({XR_FOVEART_FOVEATED_RAY_TRACING_EXTENSION_NAME, kEyeGaze});
  ASSERT_EQ(result_, XR_SUCCESS) << log;
  EXPECT_EQ(std::count(g_fake.created_with.begin(), g_fake.created_with.end(), std::string(kEyeGaze)), 1);
  EXPECT_EQ(log.find("hidden from the app"), std::string::npos) << log;
  const auto app_action = reinterpret_cast<XrAction>(std::uintptr_t{0x71});
  ASSERT_EQ(app_suggests_eye_gaze(app_action), XR_SUCCESS);
  ASSERT_EQ(g_fake.suggested.size(), 2u);
  EXPECT_EQ(g_fake.suggested[0].action, app_action);
  EXPECT_EQ(g_fake.suggested[1].action, kLayerAction);
}

TEST_F(EyeGazeChain, AppWithoutTheFoveatedExtensionGetsNothingAdded) {
  const std::string log = create({XR_KHR_COMPOSITION_LAYER_DEPTH_EXTENSION_NAME});
  ASSERT_EQ(result_, XR_SUCCESS) << log;
  EXPECT_EQ(g_fake.created_with, std::vector<std::string>{XR_KHR_COMPOSITION_LAYER_DEPTH_EXTENSION_NAME});
  EXPECT_EQ(g_fake.action_sets_created, 0);
  EXPECT_EQ(g_fake.suggest_calls, 0);
}

}  // namespace
}  // namespace foveart::layer
