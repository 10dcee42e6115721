// The device trace's indirect dispatch (gpu/shader_interface/ray_dispatch.h, the function
// shaders/device_rays.comp runs): within Vulkan's minimum maxComputeWorkGroupCount on every
// side, and enough workgroups for every ray, up to the largest eye and rays per point allowed.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>

#include "foveation/device.hpp"
#include "gpu/shader_interface/ray_dispatch.h"

namespace {

constexpr std::uint64_t kMaxRaysPerPoint = 64;    // XrFoveatedRendererCreateInfoFOVEART::raysPerPoint, config
constexpr std::uint64_t kMaxEyeSidePx = 16384;   // foveation::DisplayModel::validate
constexpr std::uint64_t kVulkanMinGroups = 65535;  // the spec's minimum maxComputeWorkGroupCount[0..2]

// The rays a view's buffers hold at most: a point per canvas pixel at most (2W x 2H, thesis 4.1),
// raysPerPoint each, no more than the device trace accepts.
std::uint64_t max_ray_capacity(std::uint64_t width_px, std::uint64_t height_px) {
  return std::min<std::uint64_t>(4 * width_px * height_px * kMaxRaysPerPoint, FOVEART_DEVICE_MAX_RAYS);
}

void expect_dispatch_covers(std::uint64_t rays) {
  SCOPED_TRACE(rays);
  std::uint32_t x = 0, y = 0;
  foveart::gpu::shader::ray_dispatch_groups(std::uint32_t(rays), x, y);
  EXPECT_LE(x, kVulkanMinGroups);
  EXPECT_LE(y, kVulkanMinGroups);
  EXPECT_GE(std::uint64_t{x} * y * FOVEART_RAY_DISPATCH_GROUP, rays);
  if (y > 1) {  // no row more than the rays need
    EXPECT_LT(std::uint64_t{x} * (y - 1) * FOVEART_RAY_DISPATCH_GROUP, rays);
  }
}

TEST(RayDispatch, CoversTheFoveEyeAtTheMostRaysPerPoint) {
  const foveart::foveation::HeadsetDescription fove = foveart::foveation::fove0();
  const std::uint64_t rays = max_ray_capacity(fove.eye_width_px, fove.eye_height_px);
  EXPECT_GT(rays, kVulkanMinGroups * FOVEART_RAY_DISPATCH_GROUP);  // one row would not do
  expect_dispatch_covers(rays);
}

TEST(RayDispatch, CoversTheLargestEyeAtTheMostRaysPerPoint) {
  expect_dispatch_covers(max_ray_capacity(kMaxEyeSidePx, kMaxEyeSidePx));
}

TEST(RayDispatch, OneRowUpTo65535Workgroups) {
  for (const std::uint32_t rays : {0u, 1u, 63u, 64u, 65u, 65535u * 64u}) {
    std::uint32_t x = 0, y = 0;
    foveart::gpu::shader::ray_dispatch_groups(rays, x, y);
    EXPECT_EQ(x, (rays + 63) / 64) << rays;
    EXPECT_EQ(y, 1u) << rays;
  }
  const std::uint64_t past_one_row[] = {65535u * 64u + 1u, 65536u * 64u, 65535u * 64u * 7u + 5u,
                                       FOVEART_DEVICE_MAX_RAYS, UINT32_MAX};
  for (const std::uint64_t rays : past_one_row) {
    expect_dispatch_covers(rays);
  }
}

}  // namespace
