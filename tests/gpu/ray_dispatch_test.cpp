// The device trace's indirect launches (gpu/shader_interface/ray_dispatch.h, the functions
// shaders/device_rays.comp runs): the compute dispatch within Vulkan's minimum
// maxComputeWorkGroupCount on every side, the traceRays launch within its minimum ray-tracing
// limits, each covering every ray, up to the largest eye and rays per point allowed.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>

#include "foveation/device.hpp"
#include "gpu/shader_interface/ray_dispatch.h"

namespace {

constexpr std::uint64_t kMaxRaysPerPoint = 64;    // XrFoveatedRendererCreateInfoFOVEART::raysPerPoint, config
constexpr std::uint64_t kMaxEyeSidePx = 16384;   // foveation::DisplayModel::validate
constexpr std::uint64_t kVulkanMinGroups = 65535;  // the spec's minimum maxComputeWorkGroupCount[0..2]
constexpr std::uint64_t kVulkanMinGroupSize = 128;  // ... maxComputeWorkGroupSize[0], [1]
constexpr std::uint64_t kVulkanMinRayLaunches = std::uint64_t{1} << 30;  // ... maxRayDispatchInvocationCount

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

// The traceRays size for `rays`: within the limits every ray-tracing device has (a launch's
// width and height by maxComputeWorkGroupCount x maxComputeWorkGroupSize, their product by
// maxRayDispatchInvocationCount); returns the launches, each tracing ceil(rays / launches) rays at most.
std::uint64_t expect_trace_rays_within_limits(std::uint64_t rays) {
  SCOPED_TRACE(rays);
  std::uint32_t width = 0, height = 0;
  foveart::gpu::shader::trace_rays_size(std::uint32_t(rays), width, height);
  EXPECT_LE(width, kVulkanMinGroups * kVulkanMinGroupSize);
  EXPECT_LE(height, kVulkanMinGroups * kVulkanMinGroupSize);
  EXPECT_GE(height, 1u);
  const std::uint64_t launches = std::uint64_t{width} * height;
  EXPECT_LE(launches, kVulkanMinRayLaunches);
  if (launches < rays) {  // the launches loop: only when the rays need every launch allowed
    EXPECT_EQ(launches, kVulkanMinRayLaunches);
  } else if (height > 1) {  // no row more than the rays need
    EXPECT_LT(std::uint64_t{width} * (height - 1), rays);
  }
  return launches;
}

TEST(RayDispatch, TraceRaysLaunchesEveryRayOfTheFoveEyeAtOnce) {
  const foveart::foveation::HeadsetDescription fove = foveart::foveation::fove0();
  const std::uint64_t rays = max_ray_capacity(fove.eye_width_px, fove.eye_height_px);
  EXPECT_GT(rays, FOVEART_TRACE_RAYS_WIDTH) << "one row would not do";
  EXPECT_GE(expect_trace_rays_within_limits(rays), rays) << "one launch per ray, no loop";
}

TEST(RayDispatch, TraceRaysLoopsPastTheLaunchLimitForTheLargestEye) {
  const std::uint64_t rays = max_ray_capacity(kMaxEyeSidePx, kMaxEyeSidePx);
  const std::uint64_t launches = expect_trace_rays_within_limits(rays);
  EXPECT_LE((rays + launches - 1) / launches, 2u) << "each launch traces two rays at most";
  for (const std::uint64_t r : {std::uint64_t{FOVEART_TRACE_RAYS_WIDTH * 3u + 1u}, std::uint64_t{UINT32_MAX}}) {
    expect_trace_rays_within_limits(r);
  }
}

TEST(RayDispatch, TraceRaysOneRowBelowItsWidth) {
  for (const std::uint32_t rays : {0u, 1u, 4097u, FOVEART_TRACE_RAYS_WIDTH}) {
    std::uint32_t width = 0, height = 0;
    foveart::gpu::shader::trace_rays_size(rays, width, height);
    EXPECT_EQ(width, rays);
    EXPECT_EQ(height, 1u);
  }
  std::uint32_t width = 0, height = 0;
  foveart::gpu::shader::trace_rays_size(FOVEART_TRACE_RAYS_WIDTH + 1u, width, height);
  EXPECT_EQ(width, FOVEART_TRACE_RAYS_WIDTH);
  EXPECT_EQ(height, 2u);
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
