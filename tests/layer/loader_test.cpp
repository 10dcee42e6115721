// The layer through the real OpenXR loader: discovery, extension gating,
// FOVEART_DISABLE, implicit-layer environment gating, create/destroy twice.
#include <cstring>
#include <algorithm>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <openxr/openxr.h>

#include "layer/XR_FOVEART_foveated_ray_tracing.h"
#include "test_env.hpp"

namespace foveart::layer::test {
namespace {

constexpr const char* kLayer = XR_FOVEART_API_LAYER_NAME;
constexpr const char* kExtension = XR_FOVEART_FOVEATED_RAY_TRACING_EXTENSION_NAME;

std::vector<std::string> api_layers() {
  uint32_t count = 0;
  EXPECT_EQ(xrEnumerateApiLayerProperties(0, &count, nullptr), XR_SUCCESS);
  std::vector<XrApiLayerProperties> props(count, XrApiLayerProperties{XR_TYPE_API_LAYER_PROPERTIES, nullptr, {}, 0, 0, {}});
  EXPECT_EQ(xrEnumerateApiLayerProperties(count, &count, props.data()), XR_SUCCESS);
  std::vector<std::string> names;
  for (const auto& p : props) names.emplace_back(p.layerName);
  return names;
}

std::vector<std::string> layer_extensions(const char* layer) {
  uint32_t count = 0;
  if (XR_FAILED(xrEnumerateInstanceExtensionProperties(layer, 0, &count, nullptr))) return {};
  std::vector<XrExtensionProperties> props(count, XrExtensionProperties{XR_TYPE_EXTENSION_PROPERTIES, nullptr, {}, 0});
  EXPECT_EQ(xrEnumerateInstanceExtensionProperties(layer, count, &count, props.data()), XR_SUCCESS);
  std::vector<std::string> names;
  for (const auto& p : props) names.emplace_back(p.extensionName);
  return names;
}

bool contains(const std::vector<std::string>& v, const std::string& s) {
  return std::find(v.begin(), v.end(), s) != v.end();
}

struct Instance {
  XrResult result = XR_ERROR_RUNTIME_FAILURE;
  XrInstance handle = XR_NULL_HANDLE;
  ~Instance() {
    if (handle != XR_NULL_HANDLE) xrDestroyInstance(handle);
  }
};

void create_instance(Instance* out, std::vector<const char*> layers, std::vector<const char*> extensions,
                     const char* app_name = "foveart_layer_test") {
  XrInstanceCreateInfo info{};
  info.type = XR_TYPE_INSTANCE_CREATE_INFO;
  std::strncpy(info.applicationInfo.applicationName, app_name, XR_MAX_APPLICATION_NAME_SIZE - 1);
  info.applicationInfo.apiVersion = XR_CURRENT_API_VERSION;
  info.enabledApiLayerCount = static_cast<uint32_t>(layers.size());
  info.enabledApiLayerNames = layers.data();
  info.enabledExtensionCount = static_cast<uint32_t>(extensions.size());
  info.enabledExtensionNames = extensions.data();
  out->result = xrCreateInstance(&info, &out->handle);
}

XrResult lookup(XrInstance instance, const char* name) {
  PFN_xrVoidFunction fn = nullptr;
  const XrResult r = xrGetInstanceProcAddr(instance, name, &fn);
  if (XR_SUCCEEDED(r) && fn == nullptr) return XR_ERROR_RUNTIME_FAILURE;
  return r;
}

TEST(Loader, LayerIsDiscoveredThroughTheExplicitManifest) {
  IsolatedEnv env;
  EXPECT_TRUE(contains(api_layers(), kLayer));
  EXPECT_TRUE(contains(layer_extensions(kLayer), kExtension));
}

TEST(Loader, ImplicitLayerNeedsItsEnableEnvironment) {
  IsolatedEnv env;
  IsolatedEnv::set("XR_API_LAYER_PATH", env.root() / "no_explicit_layers");
  const auto dir = env.root() / "data" / "openxr" / "1" / "api_layers" / "implicit.d";
  fs::create_directories(dir);
  fs::copy_file(implicit_layer_manifest(), dir / implicit_layer_manifest().filename());
  EXPECT_FALSE(contains(api_layers(), kLayer)) << "implicit layer active without FOVEART_ENABLE_IMPLICIT_LAYER";
  IsolatedEnv::set("FOVEART_ENABLE_IMPLICIT_LAYER", "1");
  EXPECT_TRUE(contains(api_layers(), kLayer));
  IsolatedEnv::set("FOVEART_DISABLE_IMPLICIT_LAYER", "1");
  EXPECT_FALSE(contains(api_layers(), kLayer)) << "disable_environment must win";
}

TEST(Loader, ExtensionFunctionsOnlyWhenEnabled) {
  FOVEART_REQUIRE_RUNTIME();
  IsolatedEnv env;
  {
    Instance without;
    create_instance(&without, {kLayer}, {});
    ASSERT_EQ(without.result, XR_SUCCESS);
    EXPECT_EQ(lookup(without.handle, "xrCreateFoveatedRendererFOVEART"), XR_ERROR_FUNCTION_UNSUPPORTED);
    EXPECT_EQ(lookup(without.handle, "xrGetFoveatedRendererStatsFOVEART"), XR_ERROR_FUNCTION_UNSUPPORTED);
    EXPECT_EQ(lookup(without.handle, "xrAcquireFoveatedRayBatchFOVEART"), XR_ERROR_FUNCTION_UNSUPPORTED);
    EXPECT_EQ(lookup(without.handle, "xrEndFrame"), XR_SUCCESS);  // pass-through still works
  }
  {
    Instance with;
    create_instance(&with, {kLayer}, {kExtension});
    ASSERT_EQ(with.result, XR_SUCCESS);
    EXPECT_EQ(lookup(with.handle, "xrCreateFoveatedRendererFOVEART"), XR_SUCCESS);
    EXPECT_EQ(lookup(with.handle, "xrDestroyFoveatedRendererFOVEART"), XR_SUCCESS);
    EXPECT_EQ(lookup(with.handle, "xrGetFoveatedRendererStatsFOVEART"), XR_SUCCESS);
    EXPECT_EQ(lookup(with.handle, "xrAcquireFoveatedRayBatchFOVEART"), XR_SUCCESS);
    EXPECT_EQ(lookup(with.handle, "xrReleaseFoveatedRayBatchFOVEART"), XR_SUCCESS);
  }
}

TEST(Loader, ExtensionRefusedWithoutTheLayer) {
  FOVEART_REQUIRE_RUNTIME();
  IsolatedEnv env;
  Instance instance;
  create_instance(&instance, {}, {kExtension});
  EXPECT_EQ(instance.result, XR_ERROR_EXTENSION_NOT_PRESENT);
}

TEST(Loader, CreateAndDestroyInstanceTwice) {
  FOVEART_REQUIRE_RUNTIME();
  IsolatedEnv env;
  for (int round = 0; round < 2; ++round) {
    Instance instance;
    create_instance(&instance, {kLayer}, {kExtension});
    ASSERT_EQ(instance.result, XR_SUCCESS) << "round " << round;
    EXPECT_EQ(lookup(instance.handle, "xrCreateFoveatedRendererFOVEART"), XR_SUCCESS) << "round " << round;
    XrInstanceProperties props{};
    props.type = XR_TYPE_INSTANCE_PROPERTIES;
    EXPECT_EQ(xrGetInstanceProperties(instance.handle, &props), XR_SUCCESS);
    EXPECT_EQ(xrDestroyInstance(instance.handle), XR_SUCCESS) << "round " << round;
    instance.handle = XR_NULL_HANDLE;
  }
}

TEST(Loader, FoveartDisableTurnsTheExtensionOff) {
  FOVEART_REQUIRE_RUNTIME();
  IsolatedEnv env;
  IsolatedEnv::set("FOVEART_DISABLE", "1");
  Instance instance;
  create_instance(&instance, {kLayer}, {kExtension});
  ASSERT_EQ(instance.result, XR_SUCCESS);
  EXPECT_EQ(lookup(instance.handle, "xrCreateFoveatedRendererFOVEART"), XR_ERROR_FUNCTION_UNSUPPORTED);
}

TEST(Loader, PerApplicationConfigDisablesOneApp) {
  FOVEART_REQUIRE_RUNTIME();
  IsolatedEnv env;
  fs::create_directories(env.root() / "config" / "foveart");
  std::ofstream(env.root() / "config" / "foveart" / "config.json")
      << R"({"applications": {"disabled_app": {"enabled": false}}})";
  {
    Instance off;
    create_instance(&off, {kLayer}, {kExtension}, "disabled_app");
    ASSERT_EQ(off.result, XR_SUCCESS);
    EXPECT_EQ(lookup(off.handle, "xrCreateFoveatedRendererFOVEART"), XR_ERROR_FUNCTION_UNSUPPORTED);
  }
  {
    Instance on;
    create_instance(&on, {kLayer}, {kExtension}, "another_app");
    ASSERT_EQ(on.result, XR_SUCCESS);
    EXPECT_EQ(lookup(on.handle, "xrCreateFoveatedRendererFOVEART"), XR_SUCCESS);
  }
}

TEST(Loader, BadConfigWarnsNamingTheKeyAndStillWorks) {
  FOVEART_REQUIRE_RUNTIME();
  IsolatedEnv env;
  const auto log_file = env.root() / "layer.log";
  const auto config = env.root() / "config.json";
  std::ofstream(config) << R"({"log_file": ")" << log_file.string() << R"(", "k": "lots"})";
  IsolatedEnv::set("FOVEART_CONFIG", config);
  Instance instance;
  create_instance(&instance, {kLayer}, {kExtension});
  ASSERT_EQ(instance.result, XR_SUCCESS);
  std::ifstream in(log_file);
  std::ostringstream buffer;
  buffer << in.rdbuf();
  const std::string text = buffer.str();
  EXPECT_NE(text.find("'k'"), std::string::npos) << text;
}

}  // namespace
}  // namespace foveart::layer::test
