// XrFoveatedRendererDensityStatsFOVEART in xrGetFoveatedRendererStatsFOVEART's
// output chain, as the other chained stats: found anywhere in the chain, its
// type and next kept, written in full; a struct of another type (unknown, or
// the density layout under a wrong type) is left as the app wrote it.
// Frames with content density fill it: tests/layer/hello_foveated_test.cpp
// (CPU trace) and gpu_engine_test.cpp (device trace).
#include <gtest/gtest.h>

#include <cstring>

#include "renderer.hpp"
#include "state.hpp"

namespace foveart::layer {
namespace {

std::shared_ptr<SessionState> density_test_session() {
  auto s = std::make_shared<SessionState>();
  s->handle = reinterpret_cast<XrSession>(uintptr_t{0xd0});
  s->instance = std::make_shared<InstanceState>();
  return s;  // has_vulkan = false: the renderer starts no threads and traces nothing
}

// A density struct of `type` whose every field the renderer would have to overwrite.
XrFoveatedRendererDensityStatsFOVEART density_filled_with_garbage(XrStructureType type) {
  XrFoveatedRendererDensityStatsFOVEART d{};
  std::memset(&d, 0x7f, sizeof d);
  d.type = type;
  d.next = nullptr;
  return d;
}

bool density_all_zero(const XrFoveatedRendererDensityStatsFOVEART& d) {
  for (int e = 0; e < 2; ++e) {
    if (d.pointsThinned[e] != 0 || d.levelsMs[e] != 0 || d.testMs[e] != 0 || d.observeMs[e] != 0 ||
        d.fillMs[e] != 0 || d.gpuFillMs[e] != 0 || d.gpuContrastMs[e] != 0) {
      return false;
    }
  }
  return true;
}

TEST(DensityStats, FoundBehindAnUnknownStructAndWrittenInFull) {
  FoveatedRenderer renderer(density_test_session(), RendererSettings{});
  auto main = XrFoveatedRendererStatsFOVEART{};
  main.type = XR_TYPE_FOVEATED_RENDERER_STATS_FOVEART;
  XrBaseOutStructure unknown{static_cast<XrStructureType>(1000900999), nullptr};
  auto input = XrFoveatedRendererInputStatsFOVEART{};
  input.type = XR_TYPE_FOVEATED_RENDERER_INPUT_STATS_FOVEART;
  auto density = density_filled_with_garbage(XR_TYPE_FOVEATED_RENDERER_DENSITY_STATS_FOVEART);
  main.next = &unknown;
  unknown.next = reinterpret_cast<XrBaseOutStructure*>(&density);
  density.next = &input;
  renderer.stats(&main);
  EXPECT_EQ(main.next, &unknown) << "the app's chain is kept";
  EXPECT_EQ(unknown.type, static_cast<XrStructureType>(1000900999));
  EXPECT_EQ(unknown.next, reinterpret_cast<XrBaseOutStructure*>(&density));
  EXPECT_EQ(density.type, XR_TYPE_FOVEATED_RENDERER_DENSITY_STATS_FOVEART);
  EXPECT_EQ(density.next, &input);
  EXPECT_TRUE(density_all_zero(density)) << "no frame yet: every field written, all 0";
  EXPECT_EQ(input.type, XR_TYPE_FOVEATED_RENDERER_INPUT_STATS_FOVEART) << "the struct after it is still reached";
}

TEST(DensityStats, TheDensityLayoutUnderAnotherTypeIsLeftAlone) {
  FoveatedRenderer renderer(density_test_session(), RendererSettings{});
  auto main = XrFoveatedRendererStatsFOVEART{};
  main.type = XR_TYPE_FOVEATED_RENDERER_STATS_FOVEART;
  auto wrong = density_filled_with_garbage(XR_TYPE_UNKNOWN);
  unsigned char before[sizeof wrong];
  std::memcpy(before, &wrong, sizeof wrong);  // bytes, padding included
  main.next = &wrong;
  renderer.stats(&main);
  EXPECT_EQ(std::memcmp(&wrong, before, sizeof wrong), 0) << "a struct the layer does not know is not written";
  EXPECT_EQ(main.next, &wrong);
}

}  // namespace
}  // namespace foveart::layer
