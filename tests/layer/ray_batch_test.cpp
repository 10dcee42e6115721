// The app-recorded trace's bookkeeping without a GPU: one batch a frame, the
// release's errors, a batch xrEndFrame takes unreleased retired with its
// semaphore generation, and the views compared bit for bit.
#include "ray_batch.hpp"

#include <gtest/gtest.h>

namespace foveart::layer {
namespace {

struct Acquired {
  XrResult result = XR_ERROR_RUNTIME_FAILURE;
  std::uint64_t id = 0, rays_ready = 0, traced = 0;
};

Acquired acquire_batch(RayBatches& batches, std::int64_t now_ns = 0) {
  Acquired a;
  a.result = batches.acquire(now_ns, {RayBatchView{}}, &a.id, &a.rays_ready, &a.traced);
  return a;
}

TEST(RayBatches, AcquireReleaseTakeGivesTheFramesWaitValue) {
  RayBatches batches;
  const Acquired a = acquire_batch(batches, 1234);
  ASSERT_EQ(a.result, XR_SUCCESS);
  EXPECT_NE(a.id, 0u);
  EXPECT_LT(a.rays_ready, a.traced) << "the app waits for the rays before it signals its colours";
  EXPECT_EQ(batches.release(a.id), XR_SUCCESS);
  const auto taken = batches.take();
  ASSERT_TRUE(taken.has_value());
  EXPECT_TRUE(taken->released);
  EXPECT_EQ(taken->id, a.id);
  EXPECT_EQ(taken->traced_value, a.traced);
  EXPECT_EQ(taken->acquired_ns, 1234);
  EXPECT_EQ(batches.semaphore_generation(), 0u);
  EXPECT_FALSE(batches.take().has_value()) << "a frame without an acquire has no batch";

  const Acquired b = acquire_batch(batches);
  ASSERT_EQ(b.result, XR_SUCCESS);
  EXPECT_GT(b.id, a.id);
  EXPECT_EQ(b.rays_ready, a.traced + 1) << "consecutive: the rays' submission waits for the last promise";
  EXPECT_EQ(batches.acquired(), 2u);
}

TEST(RayBatches, SecondAcquireBeforeEndFrameIsACallOrderError) {
  RayBatches batches;
  ASSERT_EQ(acquire_batch(batches).result, XR_SUCCESS);
  EXPECT_EQ(acquire_batch(batches).result, XR_ERROR_CALL_ORDER_INVALID);
  EXPECT_EQ(batches.acquired(), 1u);
}

TEST(RayBatches, ReleasingTwiceOrAnUnknownIdIsAValidationError) {
  RayBatches batches;
  const Acquired a = acquire_batch(batches);
  EXPECT_EQ(batches.release(0), XR_ERROR_VALIDATION_FAILURE);
  EXPECT_EQ(batches.release(a.id + 1), XR_ERROR_VALIDATION_FAILURE);
  ASSERT_EQ(batches.release(a.id), XR_SUCCESS);
  EXPECT_EQ(batches.release(a.id), XR_ERROR_VALIDATION_FAILURE) << "twice, before xrEndFrame";
  const std::optional<TakenRayBatch> taken = batches.take();
  ASSERT_TRUE(taken.has_value());
  EXPECT_FALSE(taken->released) << "released twice: retired, nobody waits for its value";
  EXPECT_TRUE(taken->released_twice);
  EXPECT_EQ(batches.retired(), 1u);
  EXPECT_EQ(batches.release(a.id), XR_ERROR_CALL_ORDER_INVALID) << "twice, after xrEndFrame: a retired batch";
  EXPECT_EQ(batches.rejected_releases(), 4u);
}

TEST(RayBatches, UnreleasedBatchIsRetiredAndItsLateReleaseRefused) {
  RayBatches batches;
  const Acquired a = acquire_batch(batches);
  const auto taken = batches.take();
  ASSERT_TRUE(taken.has_value());
  EXPECT_FALSE(taken->released) << "its views fall back; nobody waits for its value";
  EXPECT_EQ(batches.retired(), 1u);
  EXPECT_EQ(batches.semaphore_generation(), 1u) << "the app may still signal the old semaphore";
  EXPECT_EQ(batches.release(a.id), XR_ERROR_CALL_ORDER_INVALID);

  const Acquired b = acquire_batch(batches);
  ASSERT_EQ(b.result, XR_SUCCESS);
  EXPECT_EQ(b.rays_ready, 1u) << "a new semaphore's values start again";
  EXPECT_EQ(batches.release(b.id), XR_SUCCESS);
  EXPECT_TRUE(batches.take()->released);
  EXPECT_EQ(batches.semaphore_generation(), 1u);
}

TEST(RayBatches, WithdrawnBatchLeavesTheFrameFree) {
  RayBatches batches;
  const Acquired a = acquire_batch(batches);
  batches.withdraw();
  EXPECT_FALSE(batches.take().has_value());
  EXPECT_EQ(batches.release(a.id), XR_ERROR_VALIDATION_FAILURE);
  const Acquired b = acquire_batch(batches);
  ASSERT_EQ(b.result, XR_SUCCESS);
  EXPECT_EQ(b.rays_ready, a.rays_ready) << "nothing was signalled: nobody may wait for a skipped value";
  EXPECT_NE(b.id, a.id);
  EXPECT_EQ(batches.acquired(), 1u);
}

TEST(RayBatches, OnlyRecentRetiredIdsAreRemembered) {
  RayBatches batches;
  const Acquired first = acquire_batch(batches);
  (void)batches.take();
  for (std::size_t i = 0; i < RayBatches::kRetiredRemembered; ++i) {
    ASSERT_EQ(acquire_batch(batches).result, XR_SUCCESS);
    (void)batches.take();
  }
  EXPECT_EQ(batches.release(first.id), XR_ERROR_VALIDATION_FAILURE) << "forgotten: an error all the same";
  EXPECT_EQ(batches.retired(), RayBatches::kRetiredRemembered + 1);
}

TEST(RayBatches, ViewsCompareBitForBit) {
  RayBatchView a;
  a.pose.orientation.w = 1.0f;
  a.fov = {-0.8f, 0.8f, 0.7f, -0.7f};
  a.size_px = {640, 480};
  RayBatchView b = a;
  EXPECT_TRUE(same_view(a, b));
  b.pose.position.x = 1e-7f;
  EXPECT_FALSE(same_view(a, b));
  b = a;
  b.fov.angleUp = 0.7000001f;
  EXPECT_FALSE(same_view(a, b));
  b = a;
  b.size_px.height = 481;
  EXPECT_FALSE(same_view(a, b));
}

}  // namespace
}  // namespace foveart::layer
