// The one builder of engine callback batches: what an engine receives.
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include <glm/gtc/quaternion.hpp>

#include "foveation/eye_rays.hpp"
#include "foveation/ray_batch.hpp"

namespace fv = foveart::foveation;

namespace {

// Keeps what the engine was given; every ray white at 1.5 m.
struct Received {
  std::vector<float> origins_m, directions, sample_px;
  std::vector<std::uint32_t> point_index;
};
int32_t keep_batch(void* user, const FoveartRayBatch* batch) {
  auto* r = static_cast<Received*>(user);
  const std::uint32_t n = batch->ray_count;
  r->origins_m.assign(batch->origins_m, batch->origins_m + 3 * n);
  r->directions.assign(batch->directions, batch->directions + 3 * n);
  r->sample_px.assign(batch->sample_px, batch->sample_px + 2 * n);
  r->point_index.assign(batch->point_index, batch->point_index + n);
  for (std::uint32_t i = 0; i < 3 * n; ++i) batch->out_rgb[i] = 1.0f;
  for (std::uint32_t i = 0; i < n; ++i) batch->out_depth_m[i] = 1.5f;
  return FOVEART_RESULT_SUCCESS;
}

}  // namespace

// Each ray leaves the eye through its sample, bit for bit as eye_ray_direction
// through the view's map aims it: whole blocks of the vectorised aim and a
// short tail, under a tilted head off the origin.
TEST(RayBatch, AimsEachRayFromTheEyeThroughItsSample) {
  fv::EyePose pose;
  pose.position_m = glm::vec3(0.3f, 1.7f, -2.0f);
  pose.orientation = glm::normalize(glm::quat(0.8f, -0.2f, 0.5f, 0.25f));
  const FoveartEyeView view = fv::make_eye_view(1, 1280, 1440, pose, -0.9f, 0.75f, 0.85f, -0.95f);
  const fv::EyePose eye = fv::eye_pose(view);
  const fv::ScreenRayMap map = fv::screen_ray_map(fv::eye_frustum(view), eye);
  constexpr std::uint32_t kRays = 37;  // 2 x 16 + 5
  fv::RayBatch batch;
  batch.resize(64);
  std::vector<glm::vec2> samples;
  for (std::uint32_t i = 0; i < kRays; ++i) {
    samples.emplace_back(34.6f * float(i) + 0.25f, 1440.0f - 38.9f * float(i));
    batch.set_sample(i, samples.back(), 1000u + i);
  }
  Received got;
  ASSERT_EQ(batch.trace(&keep_batch, &got, view, 7, kRays), FOVEART_RESULT_SUCCESS);
  ASSERT_EQ(got.point_index.size(), kRays);
  for (std::uint32_t i = 0; i < kRays; ++i) {
    const glm::vec3 d = fv::eye_ray_direction(map, samples[i]);
    EXPECT_EQ(got.directions[3 * i], d.x) << i;
    EXPECT_EQ(got.directions[3 * i + 1], d.y) << i;
    EXPECT_EQ(got.directions[3 * i + 2], d.z) << i;
    EXPECT_EQ(got.origins_m[3 * i], eye.position_m.x) << i;
    EXPECT_EQ(got.origins_m[3 * i + 1], eye.position_m.y) << i;
    EXPECT_EQ(got.origins_m[3 * i + 2], eye.position_m.z) << i;
    EXPECT_EQ(got.sample_px[2 * i], samples[i].x) << i;
    EXPECT_EQ(got.sample_px[2 * i + 1], samples[i].y) << i;
    EXPECT_EQ(got.point_index[i], 1000u + i) << i;
    EXPECT_EQ(batch.rgb(i), glm::vec3(1.0f)) << i;
    EXPECT_EQ(batch.depth_m(i), 1.5f) << i;
  }
}
