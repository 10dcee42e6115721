// xrCreateFoveatedRendererFOVEART's create info over the layer config: every
// config key reaches the settings when the app says "use the config", every
// create-info field overrides its key, and a zero-initialised struct's enums are
// real choices (nearest neighbour, no temporal history, fixed foveation).
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <vector>
#include <string_view>

#include <gtest/gtest.h>

#include "config.hpp"
#include "renderer.hpp"

namespace foveart::layer {
namespace {

int32_t trace_nothing(void*, const FoveartRayBatch*) { return FOVEART_RESULT_SUCCESS; }

// An app that leaves every setting to the config.
XrFoveatedRendererCreateInfoFOVEART use_config_info() {
  XrFoveatedRendererCreateInfoFOVEART info{};
  info.type = XR_TYPE_FOVEATED_RENDERER_CREATE_INFO_FOVEART;
  info.traceRays = &trace_nothing;
  info.interpolation = XR_FOVEATED_INTERPOLATION_USE_CONFIG_FOVEART;
  info.k = 0;
  info.densityScale = 0.0f;
  info.raysPerPoint = 0;
  info.temporal = XR_FOVEATED_TEMPORAL_USE_CONFIG_FOVEART;
  info.gazeSource = XR_FOVEATED_GAZE_SOURCE_USE_CONFIG_FOVEART;
  info.gazeProviderSpec = nullptr;
  return info;
}

// An app that zero-initialises the struct and sets only the required fields.
XrFoveatedRendererCreateInfoFOVEART old_app_info() {
  XrFoveatedRendererCreateInfoFOVEART info{};
  info.type = XR_TYPE_FOVEATED_RENDERER_CREATE_INFO_FOVEART;
  info.traceRays = &trace_nothing;
  return info;
}

LayerConfig config_from(const std::string& json) {
  ConfigResult r;
  apply_config_text(json, "test.json", "app", &r);
  EXPECT_TRUE(r.warnings.empty()) << json << ": " << r.warnings.front();
  return r.config;
}

RendererSettings resolve(const XrFoveatedRendererCreateInfoFOVEART& info, const LayerConfig& config) {
  RendererSettings s;
  std::string error;
  EXPECT_TRUE(resolve_settings(info, config, &s, &error)) << error;
  return s;
}

std::string interpolation_name(XrFoveatedInterpolationFOVEART i) {
  switch (i) {
    case XR_FOVEATED_INTERPOLATION_NEAREST_FOVEART: return "nearest";
    case XR_FOVEATED_INTERPOLATION_MSM_FOVEART: return "msm";
    case XR_FOVEATED_INTERPOLATION_RBF_FOVEART: return "rbf";
    default: return "bad " + std::to_string(i);
  }
}

std::string gaze_source_name(XrFoveatedGazeSourceFOVEART g) {
  switch (g) {
    case XR_FOVEATED_GAZE_SOURCE_NONE_FOVEART: return "none";
    case XR_FOVEATED_GAZE_SOURCE_PROVIDER_FOVEART: return "provider";
    case XR_FOVEATED_GAZE_SOURCE_EYE_GAZE_INTERACTION_FOVEART: return "eye_gaze_interaction";
    default: return "bad " + std::to_string(g);
  }
}

// The setting a config key ends up in, spelled as the config spells it.
std::string setting_of(const RendererSettings& s, std::string_view key) {
  if (key == "interpolation") return interpolation_name(s.interpolation);
  if (key == "k") return std::to_string(s.k);
  if (key == "density_scale") return std::to_string(s.density_scale);
  if (key == "rays_per_point") return std::to_string(s.rays_per_point);
  if (key == "temporal") return s.temporal ? foveation::temporal_mode_name(*s.temporal) : "auto";
  if (key == "gaze_source") return gaze_source_name(s.gaze_source);
  if (key == "gaze_provider") return s.gaze_provider_spec;
  if (key == "content_contrast") return s.content_contrast ? std::to_string(*s.content_contrast) : "path default";
  if (key == "content_rays") return s.content_rays ? std::to_string(*s.content_rays) : "rays default";
  if (key == "content_rays_doubling_deg")
    return s.content_rays_doubling_deg ? std::to_string(*s.content_rays_doubling_deg) : "history default";
  if (key == "gaze_clock") return s.gaze_clock_display_time ? "display_time" : "steady";
  if (key == "threads") return std::to_string(s.threads);
  if (key == "cache_dir") return s.cache_dir;
  if (key == "wait_for_tables") return s.wait_for_tables ? "true" : "false";
  if (key == "reconstruction") return s.reconstruction;
  if (key == "exposure") return std::to_string(s.display.exposure);
  if (key == "tone_map") return foveation::tone_map_name(s.display.tone_map);
  ADD_FAILURE() << "no renderer setting for key '" << key << "'";
  return {};
}

struct KeyCase {
  const char* key;
  const char* json_value;    // differs from LayerConfig's default
  std::string from_config;   // the setting it gives (as setting_of spells it)
  void (*app_sets)(XrFoveatedRendererCreateInfoFOVEART*);  // nullptr: config only
  std::string from_app;      // the setting the app's value gives
};

const KeyCase kRendererKeys[] = {
    {"interpolation", R"("rbf")", "rbf",
     [](auto* i) { i->interpolation = XR_FOVEATED_INTERPOLATION_MSM_FOVEART; }, "msm"},
    {"k", "9", "9", [](auto* i) { i->k = 12; }, "12"},
    {"density_scale", "1.5", std::to_string(1.5f), [](auto* i) { i->densityScale = 2.0f; }, std::to_string(2.0f)},
    {"rays_per_point", "3", "3", [](auto* i) { i->raysPerPoint = 8; }, "8"},
    {"temporal", R"("rays")", "rays", [](auto* i) { i->temporal = XR_FOVEATED_TEMPORAL_IMAGE_FOVEART; }, "image"},
    {"gaze_source", R"("eye_gaze_interaction")", "eye_gaze_interaction",
     [](auto* i) { i->gazeSource = XR_FOVEATED_GAZE_SOURCE_NONE_FOVEART; }, "none"},
    {"gaze_provider", R"("replay:/tmp/g.csv")", "replay:/tmp/g.csv", [](auto* i) { i->gazeProviderSpec = "sim2"; },
     "sim2"},
    {"gaze_clock", R"("display_time")", "display_time", nullptr, {}},
    {"content_contrast", "0.2", std::to_string(0.2f), nullptr, {}},
    {"content_rays", "0.5", std::to_string(0.5f), nullptr, {}},
    {"content_rays_doubling_deg", "30", std::to_string(30.0f), nullptr, {}},
    {"threads", "3", "3", nullptr, {}},
    {"cache_dir", R"("/tmp/foveart-cache")", "/tmp/foveart-cache", nullptr, {}},
    {"wait_for_tables", "true", "true", nullptr, {}},
    {"reconstruction", R"("cpu")", "cpu", nullptr, {}},
    // The app sets these per frame (XrFoveatedDisplayTransformFOVEART, resolve_display below).
    {"exposure", "0.25", std::to_string(0.25f), nullptr, {}},
    {"tone_map", R"("aces")", "aces", nullptr, {}},
};

// Keys of the whole layer, not of a renderer (config_test.cpp reads them).
constexpr std::string_view kLayerKeys[] = {"enabled", "log_level", "log_file", "applications"};

TEST(ResolveSettings, EveryConfigKeyIsCovered) {
  for (std::string_view key : kConfigKeys) {
    bool covered = false;
    for (const auto& c : kRendererKeys) covered = covered || key == c.key;
    for (std::string_view k : kLayerKeys) covered = covered || key == k;
    EXPECT_TRUE(covered) << "config key '" << key << "' has no case here";
  }
}

TEST(ResolveSettings, UseConfigTakesEveryKeyFromTheConfig) {
  const RendererSettings defaults = resolve(use_config_info(), LayerConfig{});
  for (const auto& c : kRendererKeys) {
    SCOPED_TRACE(c.key);
    ASSERT_NE(setting_of(defaults, c.key), c.from_config) << "the case must differ from the default";
    const LayerConfig config = config_from("{\"" + std::string(c.key) + "\": " + c.json_value + "}");
    EXPECT_EQ(setting_of(resolve(use_config_info(), config), c.key), c.from_config);
  }
}

TEST(ResolveSettings, AppFieldOverridesItsKey) {
  for (const auto& c : kRendererKeys) {
    if (c.app_sets == nullptr) continue;
    SCOPED_TRACE(c.key);
    const LayerConfig config = config_from("{\"" + std::string(c.key) + "\": " + c.json_value + "}");
    auto info = use_config_info();
    c.app_sets(&info);
    ASSERT_NE(c.from_app, c.from_config);
    EXPECT_EQ(setting_of(resolve(info, config), c.key), c.from_app);
  }
}

TEST(ResolveSettings, EmptyProviderSpecTakesTheConfig) {
  auto info = use_config_info();
  info.gazeProviderSpec = "";
  EXPECT_EQ(resolve(info, config_from(R"({"gaze_provider": "replay:/tmp/g.csv"})")).gaze_provider_spec,
            "replay:/tmp/g.csv");
}

// The config opposite to what a zero-initialised struct asks for, in every key.
const char* kConfigAgainstZero = R"({"interpolation": "rbf", "k": 9, "density_scale": 1.5, "rays_per_point": 3,
    "temporal": "rays", "gaze_source": "eye_gaze_interaction", "gaze_provider": "replay:/tmp/g.csv"})";

TEST(ResolveSettings, ZeroEnumsAreRealChoices) {
  const RendererSettings s = resolve(old_app_info(), config_from(kConfigAgainstZero));
  EXPECT_EQ(s.interpolation, XR_FOVEATED_INTERPOLATION_NEAREST_FOVEART);
  EXPECT_EQ(s.k, 1u);  // nearest neighbour: one tap
  EXPECT_EQ(s.temporal, foveation::TemporalMode::off);
  EXPECT_EQ(s.gaze_source, XR_FOVEATED_GAZE_SOURCE_NONE_FOVEART);
  // Numbers and strings: zero or empty is the config's.
  EXPECT_EQ(s.density_scale, 1.5f);
  EXPECT_EQ(s.rays_per_point, 3u);
  EXPECT_EQ(s.gaze_provider_spec, "replay:/tmp/g.csv");
}

TEST(ResolveSettings, AppEnumsOverrideTheConfig) {
  auto info = old_app_info();
  info.interpolation = XR_FOVEATED_INTERPOLATION_MSM_FOVEART;
  info.temporal = XR_FOVEATED_TEMPORAL_IMAGE_FOVEART;
  info.gazeSource = XR_FOVEATED_GAZE_SOURCE_PROVIDER_FOVEART;
  const LayerConfig config = config_from(kConfigAgainstZero);
  RendererSettings s = resolve(info, config);
  EXPECT_EQ(s.interpolation, XR_FOVEATED_INTERPOLATION_MSM_FOVEART);
  EXPECT_EQ(s.k, 9u);  // k = 0: the config's
  EXPECT_EQ(s.temporal, foveation::TemporalMode::image);
  EXPECT_EQ(s.gaze_source, XR_FOVEATED_GAZE_SOURCE_PROVIDER_FOVEART);
  info.temporal = XR_FOVEATED_TEMPORAL_RAYS_FOVEART;
  EXPECT_EQ(resolve(info, config).temporal, foveation::TemporalMode::rays);
  info.temporal = static_cast<XrFoveatedTemporalFOVEART>(3);  // no such mode: refused, named
  RendererSettings refused;
  std::string error;
  EXPECT_FALSE(resolve_settings(info, config, &refused, &error));
  EXPECT_NE(error.find("temporal 3"), std::string::npos) << error;
}

// "auto" (the default) is the path's own: the render cache where the GPU reconstructs, the image
// history on the CPU path; a mode the config or the app names holds on both paths.
TEST(ResolveSettings, AutoTemporalFollowsTheReconstructionPath) {
  const RendererSettings automatic = resolve(use_config_info(), LayerConfig{});
  EXPECT_FALSE(automatic.temporal.has_value());
  EXPECT_EQ(temporal_for_path(automatic, /*reconstruct_on_gpu=*/true), foveation::TemporalMode::rays);
  EXPECT_EQ(temporal_for_path(automatic, /*reconstruct_on_gpu=*/false), foveation::TemporalMode::image);
  const RendererSettings off = resolve(use_config_info(), config_from(R"({"temporal": "off"})"));
  EXPECT_EQ(temporal_for_path(off, true), foveation::TemporalMode::off);
  EXPECT_EQ(temporal_for_path(off, false), foveation::TemporalMode::off);
}

// A key read as a number in [0, 1] or 0 for off (content_contrast, content_rays): out of that
// range or not a number it is refused with one warning naming the key and the range, and stays unset.
void expect_unit_or_off_refused(const char* key, std::optional<float> LayerConfig::*setting) {
  for (const char* bad : {"-0.1", "1.5", "\"high\""}) {
    ConfigResult r;
    apply_config_text(std::string("{\"") + key + "\": " + bad + "}", "test.json", "app", &r);
    EXPECT_FALSE((r.config.*setting).has_value()) << key << " " << bad;
    ASSERT_EQ(r.warnings.size(), 1u) << key << " " << bad;
    EXPECT_NE(r.warnings[0].find(key), std::string::npos) << r.warnings[0];
    EXPECT_NE(r.warnings[0].find("[0, 1]"), std::string::npos) << r.warnings[0];
  }
}

// The eccentricity over which content_rays doubles, unset, follows the view's history: every 30
// degrees with the render cache ("rays"), off with the image history or none. A value the config
// names holds with any history, 0 (off) too; out of 0 to 90 degrees it is refused with one
// warning naming the key and the range, and the default stays.
TEST(ResolveSettings, UnsetContentRaysDoublingFollowsTheHistory) {
  using foveation::TemporalMode;
  const RendererSettings automatic = resolve(use_config_info(), LayerConfig{});
  EXPECT_FALSE(automatic.content_rays_doubling_deg.has_value());
  EXPECT_EQ(content_rays_doubling_for(automatic, TemporalMode::rays), foveation::kDefaultRaysDoublingEccDeg);
  EXPECT_EQ(foveation::kDefaultRaysDoublingEccDeg, 30.0f);
  EXPECT_EQ(content_rays_doubling_for(automatic, TemporalMode::image), 0.0f);
  EXPECT_EQ(content_rays_doubling_for(automatic, TemporalMode::off), 0.0f);
  for (const float d : {0.0f, 20.0f}) {
    const RendererSettings named =
        resolve(use_config_info(), config_from("{\"content_rays_doubling_deg\": " + std::to_string(d) + "}"));
    for (const TemporalMode mode : {TemporalMode::rays, TemporalMode::image, TemporalMode::off})
      EXPECT_EQ(content_rays_doubling_for(named, mode), d) << foveation::temporal_mode_name(mode);
  }
  for (const char* bad : {"-1", "91", "\"far\"", "null"}) {
    ConfigResult r;
    apply_config_text(std::string("{\"content_rays_doubling_deg\": ") + bad + "}", "test.json", "app", &r);
    EXPECT_FALSE(r.config.content_rays_doubling_deg.has_value()) << bad;
    ASSERT_EQ(r.warnings.size(), 1u) << bad;
    EXPECT_NE(r.warnings[0].find("content_rays_doubling_deg"), std::string::npos) << r.warnings[0];
    EXPECT_NE(r.warnings[0].find("[0, 90]"), std::string::npos) << r.warnings[0];
  }
}

// Content density unset is the path's own: on where the GPU reconstructs, off on the CPU path;
// a contrast the config names holds on both, 0 (off) too; out of [0, 1] it is refused.
TEST(ResolveSettings, UnsetContentContrastFollowsTheReconstructionPath) {
  const RendererSettings automatic = resolve(use_config_info(), LayerConfig{});
  EXPECT_FALSE(automatic.content_contrast.has_value());
  EXPECT_EQ(content_contrast_for_path(automatic, /*reconstruct_on_gpu=*/true), kDeviceContentContrast);
  EXPECT_EQ(content_contrast_for_path(automatic, /*reconstruct_on_gpu=*/false), 0.0f);
  for (const float c : {0.0f, 0.5f}) {
    const RendererSettings named =
        resolve(use_config_info(), config_from("{\"content_contrast\": " + std::to_string(c) + "}"));
    EXPECT_EQ(content_contrast_for_path(named, true), c);
    EXPECT_EQ(content_contrast_for_path(named, false), c);
  }
  expect_unit_or_off_refused("content_contrast", &LayerConfig::content_contrast);
}

// Rays per point by contrast unset are on where a point casts several rays, from the app's rays
// per point or the config's alike, at density scale 1 or above; one ray per point has none to
// vary, and a denser scale keeps them off. A contrast the config names holds at any rays per
// point and scale, 0 (off) too; out of [0, 1] it is refused.
TEST(ResolveSettings, UnsetContentRaysVaryWhereAPointCastsSeveral) {
  const RendererSettings one_ray = resolve(use_config_info(), LayerConfig{});
  EXPECT_FALSE(one_ray.content_rays.has_value());
  EXPECT_EQ(content_rays_for(one_ray), 0.0f);
  const RendererSettings from_config = resolve(use_config_info(), config_from(R"({"rays_per_point": 4})"));
  EXPECT_EQ(content_rays_for(from_config), foveation::kDefaultRaysContrast);
  auto info = use_config_info();
  info.raysPerPoint = 2;
  EXPECT_EQ(content_rays_for(resolve(info, LayerConfig{})), foveation::kDefaultRaysContrast);
  EXPECT_GT(foveation::kDefaultRaysContrast, 0.0f);
  info.densityScale = 2.0f;
  EXPECT_EQ(content_rays_for(resolve(info, LayerConfig{})), foveation::kDefaultRaysContrast);
  info.densityScale = 0.7f;
  EXPECT_EQ(content_rays_for(resolve(info, LayerConfig{})), 0.0f);
  EXPECT_EQ(content_rays_for(resolve(use_config_info(), config_from(R"({"rays_per_point": 4, "density_scale": 0.7})"))),
            0.0f);
  for (const float c : {0.0f, 0.25f}) {
    const std::string text =
        "{\"rays_per_point\": 16, \"density_scale\": 0.7, \"content_rays\": " + std::to_string(c) + "}";
    EXPECT_EQ(content_rays_for(resolve(use_config_info(), config_from(text))), c);
  }
  EXPECT_EQ(content_rays_for(resolve(use_config_info(), config_from(R"({"content_rays": 0.25})"))), 0.25f);
  expect_unit_or_off_refused("content_rays", &LayerConfig::content_rays);
}

TEST(ResolveSettings, NearestNeighbourUsesOneTap) {
  auto info = use_config_info();
  info.interpolation = XR_FOVEATED_INTERPOLATION_NEAREST_FOVEART;
  info.k = 10;
  EXPECT_EQ(resolve(info, LayerConfig{}).k, 1u);
  // Nearest from the config, k from the app: still one tap.
  info.interpolation = XR_FOVEATED_INTERPOLATION_USE_CONFIG_FOVEART;
  EXPECT_EQ(resolve(info, config_from(R"({"interpolation": "nearest"})")).k, 1u);
}

TEST(ResolveSettings, BadFieldsAreNamed) {
  struct Case {
    void (*edit)(XrFoveatedRendererCreateInfoFOVEART*);
    const char* field;
  };
  const Case cases[] = {
      {[](auto* i) { i->traceRays = nullptr; }, "traceRays"},
      {[](auto* i) { i->k = 21; }, "k"},
      {[](auto* i) { i->densityScale = NAN; }, "densityScale"},
      {[](auto* i) { i->densityScale = -1.0f; }, "densityScale"},
      {[](auto* i) { i->raysPerPoint = 65; }, "raysPerPoint"},
      {[](auto* i) { i->interpolation = static_cast<XrFoveatedInterpolationFOVEART>(7); }, "interpolation"},
      {[](auto* i) { i->interpolation = static_cast<XrFoveatedInterpolationFOVEART>(0x7FFFFFFD); }, "interpolation"},
      {[](auto* i) { i->gazeSource = static_cast<XrFoveatedGazeSourceFOVEART>(9); }, "gazeSource"},
      {[](auto* i) { i->gazeSource = static_cast<XrFoveatedGazeSourceFOVEART>(0x7FFFFFFD); }, "gazeSource"},
  };
  for (const auto& c : cases) {
    auto info = use_config_info();
    c.edit(&info);
    RendererSettings s;
    std::string error;
    EXPECT_FALSE(resolve_settings(info, LayerConfig{}, &s, &error)) << c.field;
    EXPECT_NE(error.find(c.field), std::string::npos) << error;
  }
}

// The app-recorded trace chained: no callback needed, its queue families kept;
// a count without indices is named.
TEST(ResolveSettings, AppRecordedTraceStandsInForTheCallback) {
  auto info = use_config_info();
  info.traceRays = nullptr;
  const uint32_t families[2] = {2, 0};
  XrFoveatedAppTraceInfoFOVEART app{};
  app.type = XR_TYPE_FOVEATED_APP_TRACE_INFO_FOVEART;
  app.queueFamilyIndexCount = 2;
  app.queueFamilyIndices = families;
  info.next = &app;
  RendererSettings s;
  std::string error;
  ASSERT_TRUE(resolve_settings(info, LayerConfig{}, &s, &error)) << error;
  EXPECT_TRUE(s.app_trace);
  EXPECT_EQ(s.app_queue_families, (std::vector<uint32_t>{2, 0}));
  EXPECT_EQ(s.trace_rays_device, nullptr);
  app.queueFamilyIndices = nullptr;
  EXPECT_FALSE(resolve_settings(info, LayerConfig{}, &s, &error));
  EXPECT_NE(error.find("queueFamilyIndices"), std::string::npos) << error;
  info.next = nullptr;
  EXPECT_FALSE(resolve_settings(info, LayerConfig{}, &s, &error)) << "no trace at all";
  EXPECT_NE(error.find("traceRays"), std::string::npos) << error;
}

// A frame's XrFoveatedDisplayTransformFOVEART over the config's transform: each
// field overrides unless it says "use the config"; a bad field keeps the config's
// value and says what was wrong.
TEST(ResolveDisplay, TheFramesStructOverridesTheConfigFieldByField) {
  const foveation::DisplayTransform configured{0.5f, foveation::ToneMap::pbr_neutral};
  std::string error;
  EXPECT_EQ(resolve_display(nullptr, configured, &error), configured);
  XrFoveatedDisplayTransformFOVEART chained{};
  chained.type = XR_TYPE_FOVEATED_DISPLAY_TRANSFORM_FOVEART;
  chained.exposure = 0.0f;
  chained.toneMap = XR_FOVEATED_TONE_MAP_USE_CONFIG_FOVEART;
  EXPECT_EQ(resolve_display(&chained, configured, &error), configured);
  chained.exposure = 2.0f;
  EXPECT_EQ(resolve_display(&chained, configured, &error),
            (foveation::DisplayTransform{2.0f, foveation::ToneMap::pbr_neutral}));
  chained.toneMap = XR_FOVEATED_TONE_MAP_NONE_FOVEART;  // zero is a real choice, as for the create info's enums
  EXPECT_EQ(resolve_display(&chained, configured, &error), (foveation::DisplayTransform{2.0f, foveation::ToneMap::none}));
  chained.toneMap = XR_FOVEATED_TONE_MAP_ACES_FOVEART;
  EXPECT_EQ(resolve_display(&chained, configured, &error).tone_map, foveation::ToneMap::aces);
  EXPECT_TRUE(error.empty()) << error;
}

TEST(ResolveDisplay, BadFieldsKeepTheConfigsValueAndSaySo) {
  const foveation::DisplayTransform configured{0.5f, foveation::ToneMap::aces};
  XrFoveatedDisplayTransformFOVEART chained{};
  chained.type = XR_TYPE_FOVEATED_DISPLAY_TRANSFORM_FOVEART;
  chained.toneMap = XR_FOVEATED_TONE_MAP_USE_CONFIG_FOVEART;
  for (float bad : {-1.0f, std::nanf(""), std::numeric_limits<float>::infinity()}) {
    chained.exposure = bad;
    std::string error;
    EXPECT_EQ(resolve_display(&chained, configured, &error), configured) << bad;
    EXPECT_NE(error.find("exposure"), std::string::npos) << bad;
  }
  chained.exposure = 0.0f;
  chained.toneMap = static_cast<XrFoveatedToneMapFOVEART>(7);
  std::string error;
  EXPECT_EQ(resolve_display(&chained, configured, &error), configured);
  EXPECT_NE(error.find("toneMap 7"), std::string::npos) << error;
}

}  // namespace
}  // namespace foveart::layer
