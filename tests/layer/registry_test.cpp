// The registry answers for a session only with its own renderers and
// swapchains: what xrEndFrame checks an app's frame against.
#include <gtest/gtest.h>

#include <cstring>

#include "renderer.hpp"
#include "state.hpp"

namespace foveart::layer {
namespace {

XrSession session_handle(uintptr_t id) { return reinterpret_cast<XrSession>(id); }
XrSwapchain swapchain_handle(uintptr_t id) { return reinterpret_cast<XrSwapchain>(id); }

std::shared_ptr<SessionState> session_state(XrSession handle) {
  auto s = std::make_shared<SessionState>();
  s->handle = handle;
  s->instance = std::make_shared<InstanceState>();
  return s;  // has_vulkan = false: the renderer starts no threads
}

TEST(Registry, RendererOfAnotherSessionIsNotServedButNamed) {
  Registry& registry = Registry::get();
  const XrSession a = session_handle(0xa0), b = session_handle(0xb0);
  registry.add_session(session_state(a));
  registry.add_session(session_state(b));
  auto renderer = std::make_shared<FoveatedRenderer>(session_state(a), RendererSettings{});
  const auto handle = registry.add_renderer(a, renderer);

  std::shared_ptr<FoveatedRenderer> other;
  EXPECT_EQ(registry.renderer_of_session(handle, a, &other), renderer);
  EXPECT_EQ(other, nullptr);
  EXPECT_EQ(registry.renderer_of_session(handle, b, &other), nullptr);
  EXPECT_EQ(other, renderer) << "the foreign renderer is named so it can count the misuse";
  const auto unknown = reinterpret_cast<XrFoveatedRendererFOVEART>(uintptr_t{0xdead});
  EXPECT_EQ(registry.renderer_of_session(unknown, a, &other), nullptr);
  EXPECT_EQ(other, nullptr);

  renderer->count_foreign_session_layer();
  auto main = XrFoveatedRendererStatsFOVEART{};
  main.type = XR_TYPE_FOVEATED_RENDERER_STATS_FOVEART;
  auto input = XrFoveatedRendererInputStatsFOVEART{};
  input.type = XR_TYPE_FOVEATED_RENDERER_INPUT_STATS_FOVEART;
  main.next = &input;
  renderer->stats(&main);
  EXPECT_EQ(main.next, &input) << "the app's chain is kept";
  EXPECT_EQ(input.foreignSessionLayers, 1u);

  registry.remove_session(a);
  registry.remove_session(b);
  EXPECT_EQ(registry.renderer(handle), nullptr);
}

TEST(Registry, SwapchainExtentsBelongToTheirSession) {
  Registry& registry = Registry::get();
  const XrSession a = session_handle(0xa1), b = session_handle(0xb1);
  registry.add_session(session_state(a));
  registry.add_session(session_state(b));
  const XrSwapchain sc = swapchain_handle(0x5c);
  registry.add_swapchain(sc, SwapchainExtent{a, 640, 480, 2});
  ASSERT_TRUE(registry.swapchain(sc, a).has_value());
  EXPECT_EQ(registry.swapchain(sc, a)->width_px, 640u);
  EXPECT_FALSE(registry.swapchain(sc, b).has_value()) << "another session's swapchain is unknown to this one";
  registry.remove_session(a);  // a session's swapchains go with it
  EXPECT_FALSE(registry.swapchain(sc, a).has_value());
  registry.remove_session(b);
}

// A session without a Vulkan binding (xrCreateFoveatedRendererFOVEART refuses
// one; a renderer that has none anyway) forwards every view untouched.
TEST(Registry, RendererOfASessionWithoutVulkanForwardsEveryView) {
  auto renderer = std::make_shared<FoveatedRenderer>(session_state(session_handle(0xc0)), RendererSettings{});
  XrCompositionLayerProjectionView views[2]{};
  views[0].subImage.imageRect.extent = {64, 48};
  views[1] = views[0];
  XrCompositionLayerProjection layer{};
  layer.type = XR_TYPE_COMPOSITION_LAYER_PROJECTION;
  layer.viewCount = 2;
  layer.views = views;
  XrCompositionLayerProjectionView out[2] = {views[0], views[1]};
  EXPECT_EQ(renderer->render(1, layer, out, {true, true}, nullptr), 0u);
  EXPECT_EQ(std::memcmp(out, views, sizeof views), 0) << "views forwarded as sent";
  auto stats = XrFoveatedRendererStatsFOVEART{};
  stats.type = XR_TYPE_FOVEATED_RENDERER_STATS_FOVEART;
  renderer->stats(&stats);
  EXPECT_EQ(stats.framesFallback, 2u);
  EXPECT_EQ(stats.framesTraced, 0u);
  EXPECT_EQ(stats.fallbackFlags, XR_FOVEATED_FALLBACK_UNAVAILABLE_BIT_FOVEART);
}

}  // namespace
}  // namespace foveart::layer
