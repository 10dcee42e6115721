// The opt-in struct is removed from the projection layer's next chain at any
// position, and the app's own structs are never written.
#include <cstring>

#include <gtest/gtest.h>

#include "layer/XR_FOVEART_foveated_ray_tracing.h"
#include "next_chain.hpp"

namespace foveart::layer {
namespace {

struct AppChain {
  XrCompositionLayerColorScaleBiasKHR scale{XR_TYPE_COMPOSITION_LAYER_COLOR_SCALE_BIAS_KHR, nullptr,
                                             {0.5f, 0.25f, 1.0f, 1.0f}, {0.1f, 0.0f, 0.0f, 0.0f}};
  XrFoveatedRayTracingLayerFOVEART opt_in{XR_TYPE_FOVEATED_RAY_TRACING_LAYER_FOVEART, nullptr,
                                          reinterpret_cast<XrFoveatedRendererFOVEART>(std::uintptr_t{7})};
  XrCompositionLayerSecureContentFB secure{XR_TYPE_COMPOSITION_LAYER_SECURE_CONTENT_FB, nullptr,
                                           XR_COMPOSITION_LAYER_SECURE_CONTENT_EXCLUDE_LAYER_BIT_FB};
};

std::vector<XrStructureType> types_of(const void* head) {
  std::vector<XrStructureType> out;
  for (auto* s = static_cast<const XrBaseInStructure*>(head); s != nullptr; s = s->next) out.push_back(s->type);
  return out;
}

TEST(NextChain, OptInFirstIsSkippedWithoutCopies) {
  AppChain app;
  app.opt_in.next = &app.scale;
  app.scale.next = &app.secure;
  ChainCopies copies;
  const void* head = nullptr;
  ASSERT_TRUE(copies.without(&app.opt_in, &app.opt_in, &head));
  EXPECT_EQ(head, &app.scale);
  EXPECT_EQ(app.opt_in.next, &app.scale);
}

TEST(NextChain, OptInInTheMiddleIsRemovedFromACopy) {
  AppChain app;
  app.scale.next = &app.opt_in;
  app.opt_in.next = &app.secure;
  const AppChain before = app;
  ChainCopies copies;
  const void* head = nullptr;
  ASSERT_TRUE(copies.without(&app.scale, &app.opt_in, &head));
  EXPECT_EQ(types_of(head), (std::vector<XrStructureType>{XR_TYPE_COMPOSITION_LAYER_COLOR_SCALE_BIAS_KHR,
                                                          XR_TYPE_COMPOSITION_LAYER_SECURE_CONTENT_FB}));
  EXPECT_NE(head, &app.scale);  // a copy ...
  const auto* scale = static_cast<const XrCompositionLayerColorScaleBiasKHR*>(head);
  EXPECT_EQ(scale->colorScale.g, 0.25f);  // ... with the app's values
  EXPECT_EQ(scale->colorBias.r, 0.1f);
  EXPECT_EQ(scale->next, &app.secure);  // the tail is shared
  // The app's structs are untouched.
  EXPECT_EQ(app.scale.next, &app.opt_in);
  EXPECT_EQ(app.opt_in.next, &app.secure);
  EXPECT_EQ(std::memcmp(&app.scale, &before.scale, sizeof(app.scale)), 0);
}

TEST(NextChain, OptInLastEndsTheCopiedChain) {
  AppChain app;
  app.secure.next = &app.scale;
  app.scale.next = &app.opt_in;
  ChainCopies copies;
  const void* head = nullptr;
  ASSERT_TRUE(copies.without(&app.secure, &app.opt_in, &head));
  EXPECT_EQ(types_of(head), (std::vector<XrStructureType>{XR_TYPE_COMPOSITION_LAYER_SECURE_CONTENT_FB,
                                                          XR_TYPE_COMPOSITION_LAYER_COLOR_SCALE_BIAS_KHR}));
  EXPECT_EQ(app.scale.next, &app.opt_in);
}

TEST(NextChain, UnknownStructBeforeTheOptInLeavesTheChainAsIs) {
  AppChain app;
  XrBaseInStructure unknown{static_cast<XrStructureType>(1234567),
                            reinterpret_cast<const XrBaseInStructure*>(&app.opt_in)};
  ChainCopies copies;
  const void* head = nullptr;
  EXPECT_FALSE(copies.without(&unknown, &app.opt_in, &head));
  EXPECT_EQ(head, &unknown);
  EXPECT_EQ(static_cast<const void*>(unknown.next), &app.opt_in);
}

TEST(NextChain, NodeNotInTheChainIsReported) {
  AppChain app;
  app.scale.next = &app.secure;
  ChainCopies copies;
  const void* head = nullptr;
  EXPECT_FALSE(copies.without(&app.scale, &app.opt_in, &head));
  EXPECT_EQ(head, &app.scale);
}

TEST(NextChain, SizesComeFromTheRegistry) {
  EXPECT_EQ(structure_size(XR_TYPE_COMPOSITION_LAYER_PROJECTION), sizeof(XrCompositionLayerProjection));
  EXPECT_EQ(structure_size(XR_TYPE_COMPOSITION_LAYER_COLOR_SCALE_BIAS_KHR), sizeof(XrCompositionLayerColorScaleBiasKHR));
  EXPECT_EQ(structure_size(static_cast<XrStructureType>(1234567)), 0u);
}

}  // namespace
}  // namespace foveart::layer

namespace foveart::layer {
namespace {

// Found by tests/fuzz/fuzz_next_chain: a node whose type is a negative 32-bit
// value (any garbage an app leaves there) was loaded as an XrStructureType, which
// is undefined behaviour outside the enum's range (UBSan: "not a valid value for
// type 'XrStructureType'"). The walk reads types as integers.
TEST(NextChain, TypeOutsideTheEnumRangeIsReadAsAnInteger) {
  XrBaseInStructure garbage{};
  const std::int32_t raw = static_cast<std::int32_t>(0x9B3BF110u);
  std::memcpy(&garbage.type, &raw, sizeof raw);
  XrFoveatedRayTracingLayerFOVEART opt_in{XR_TYPE_FOVEATED_RAY_TRACING_LAYER_FOVEART, nullptr, XR_NULL_HANDLE};
  garbage.next = reinterpret_cast<const XrBaseInStructure*>(&opt_in);
  EXPECT_EQ(type_of(&garbage), raw);
  EXPECT_EQ(structure_size(raw), 0u);
  EXPECT_EQ(find_in_chain<XrFoveatedRayTracingLayerFOVEART>(&garbage, XR_TYPE_FOVEATED_RAY_TRACING_LAYER_FOVEART),
            &opt_in);
  ChainCopies copies;
  const void* head = nullptr;
  EXPECT_FALSE(copies.without(&garbage, &opt_in, &head)) << "a node of unknown size cannot be copied";
  EXPECT_EQ(head, &garbage);
}

// A chain that loops (invalid usage) ends the walk instead of hanging the app's thread.
TEST(NextChain, LoopingChainEndsTheWalk) {
  // Real structs of the type they claim: the walk copies the registry's size of each.
  XrCompositionLayerDepthInfoKHR a{};
  XrCompositionLayerDepthInfoKHR b{};
  a.type = b.type = XR_TYPE_COMPOSITION_LAYER_DEPTH_INFO_KHR;
  a.next = &b;
  b.next = &a;
  EXPECT_EQ(find_in_chain<XrBaseInStructure>(&a, XR_TYPE_FOVEATED_RAY_TRACING_LAYER_FOVEART), nullptr);
  XrFoveatedRayTracingLayerFOVEART never_reached{XR_TYPE_FOVEATED_RAY_TRACING_LAYER_FOVEART, nullptr, XR_NULL_HANDLE};
  ChainCopies copies;
  const void* head = nullptr;
  EXPECT_FALSE(copies.without(&a, &never_reached, &head));
}

}  // namespace
}  // namespace foveart::layer
