// xrCreateFoveatedRendererFOVEART's create info over the config defaults.
#include <cmath>

#include <gtest/gtest.h>

#include "renderer.hpp"

namespace foveart::layer {
namespace {

int32_t trace_nothing(void*, const FoveartRayBatch*) { return FOVEART_RESULT_SUCCESS; }

XrFoveatedRendererCreateInfoFOVEART valid_info() {
  XrFoveatedRendererCreateInfoFOVEART info{};
  info.type = XR_TYPE_FOVEATED_RENDERER_CREATE_INFO_FOVEART;
  info.traceRays = &trace_nothing;
  info.interpolation = XR_FOVEATED_INTERPOLATION_RBF_FOVEART;
  info.gazeSource = XR_FOVEATED_GAZE_SOURCE_PROVIDER_FOVEART;
  return info;
}

TEST(ResolveSettings, ZeroFieldsTakeTheConfig) {
  LayerConfig config;
  config.k = 9;
  config.rays_per_point = 3;
  config.density_scale = 1.5f;
  config.gaze_provider = "replay:/tmp/g.csv";
  RendererSettings s;
  std::string error;
  ASSERT_TRUE(resolve_settings(valid_info(), config, &s, &error)) << error;
  EXPECT_EQ(s.k, 9u);
  EXPECT_EQ(s.rays_per_point, 3u);
  EXPECT_EQ(s.density_scale, 1.5f);
  EXPECT_EQ(s.gaze_provider_spec, "replay:/tmp/g.csv");
  EXPECT_EQ(s.interpolation, XR_FOVEATED_INTERPOLATION_RBF_FOVEART);
}

TEST(ResolveSettings, AppFieldsWin) {
  auto info = valid_info();
  info.k = 12;
  info.raysPerPoint = 8;
  info.densityScale = 2.0f;
  info.taaEnable = XR_TRUE;
  info.gazeProviderSpec = "sim";
  RendererSettings s;
  std::string error;
  ASSERT_TRUE(resolve_settings(info, LayerConfig{}, &s, &error)) << error;
  EXPECT_EQ(s.k, 12u);
  EXPECT_EQ(s.rays_per_point, 8u);
  EXPECT_EQ(s.density_scale, 2.0f);
  EXPECT_TRUE(s.taa);
  EXPECT_EQ(s.gaze_provider_spec, "sim");
}

TEST(ResolveSettings, NearestNeighbourUsesOneTap) {
  auto info = valid_info();
  info.interpolation = XR_FOVEATED_INTERPOLATION_NEAREST_FOVEART;
  info.k = 10;
  RendererSettings s;
  std::string error;
  ASSERT_TRUE(resolve_settings(info, LayerConfig{}, &s, &error));
  EXPECT_EQ(s.k, 1u);
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
      {[](auto* i) { i->gazeSource = static_cast<XrFoveatedGazeSourceFOVEART>(9); }, "gazeSource"},
  };
  for (const auto& c : cases) {
    auto info = valid_info();
    c.edit(&info);
    RendererSettings s;
    std::string error;
    EXPECT_FALSE(resolve_settings(info, LayerConfig{}, &s, &error)) << c.field;
    EXPECT_NE(error.find(c.field), std::string::npos) << error;
  }
}

}  // namespace
}  // namespace foveart::layer
