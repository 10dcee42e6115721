// How the sample engines read a batch: what they refuse, and the rays they trace.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include <glm/gtc/quaternion.hpp>

#include "foveation/eye_rays.hpp"
#include "foveation/ray_batch_reader.hpp"

namespace fv = foveart::foveation;

namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

FoveartEyeView tilted_view() {
  fv::EyePose pose;
  pose.position_m = glm::vec3(0.3f, 1.7f, -2.0f);
  pose.orientation = glm::normalize(glm::quat(0.8f, -0.2f, 0.5f, 0.25f));
  return fv::make_eye_view(1, 1280, 1440, pose, -0.9f, 0.75f, 0.85f, -0.95f);
}

// Rays through `samples` of `view`, given both ways: explicit rays and the view.
struct Batch {
  FoveartEyeView view = tilted_view();
  std::vector<float> origins_m, directions, sample_px, rgb, depth_m;
  FoveartRayBatch batch{};

  explicit Batch(const std::vector<glm::vec2>& samples) {
    const fv::EyePose eye = fv::eye_pose(view);
    const fv::ScreenRayMap map = fv::screen_ray_map(fv::eye_frustum(view), eye);
    for (const glm::vec2 s : samples) {
      const glm::vec3 d = fv::eye_ray_direction(map, s);
      origins_m.insert(origins_m.end(), {eye.position_m.x, eye.position_m.y, eye.position_m.z});
      directions.insert(directions.end(), {d.x, d.y, d.z});
      sample_px.insert(sample_px.end(), {s.x, s.y});
    }
    rgb.resize(3 * samples.size());
    depth_m.resize(samples.size());
    batch.type = FOVEART_TYPE_RAY_BATCH;
    batch.size = sizeof(FoveartRayBatch);
    batch.view = &view;
    batch.ray_count = std::uint32_t(samples.size());
    batch.origins_m = origins_m.data();
    batch.directions = directions.data();
    batch.sample_px = sample_px.data();
    batch.out_rgb = rgb.data();
    batch.out_depth_m = depth_m.data();
  }
};

std::int32_t read(const FoveartRayBatch& batch) {
  fv::RayBatchReader reader;
  return fv::RayBatchReader::read(&batch, &reader);
}

}  // namespace

TEST(RayBatchReader, RefusesABatchAnEngineCannotRead) {
  fv::RayBatchReader reader;
  EXPECT_EQ(fv::RayBatchReader::read(nullptr, &reader), FOVEART_RESULT_ERROR_INVALID_ARGUMENT);
  const Batch good({{10.5f, 20.5f}});
  ASSERT_EQ(read(good.batch), FOVEART_RESULT_SUCCESS);
  {
    Batch b({{10.5f, 20.5f}});
    b.batch.type = FOVEART_TYPE_EYE_VIEW;
    EXPECT_EQ(read(b.batch), FOVEART_RESULT_ERROR_INVALID_ARGUMENT) << "wrong type";
  }
  {
    Batch b({{10.5f, 20.5f}});
    b.batch.size = offsetof(FoveartRayBatch, out_rgb);
    EXPECT_EQ(read(b.batch), FOVEART_RESULT_ERROR_INVALID_ARGUMENT) << "too small to hold out_rgb";
  }
  {
    Batch b({{10.5f, 20.5f}});
    b.batch.out_rgb = nullptr;
    EXPECT_EQ(read(b.batch), FOVEART_RESULT_ERROR_INVALID_ARGUMENT) << "nowhere to write";
  }
  {
    Batch b({{10.5f, 20.5f}});
    b.batch.directions = nullptr;
    b.batch.sample_px = nullptr;
    EXPECT_EQ(read(b.batch), FOVEART_RESULT_ERROR_INVALID_ARGUMENT) << "origins alone, no samples";
  }
  {
    Batch b({{10.5f, 20.5f}});
    b.batch.origins_m = nullptr;
    b.view.width_px = 0;
    EXPECT_EQ(read(b.batch), FOVEART_RESULT_ERROR_INVALID_ARGUMENT) << "an empty view";
  }
  for (const auto& spoil : std::vector<void (*)(FoveartEyeView&)>{
           [](FoveartEyeView& v) { v.position_m[1] = kNaN; }, [](FoveartEyeView& v) { v.position_m[0] = 2e9f; },
           [](FoveartEyeView& v) { v.orientation_xyzw[3] = 2.0f; },
           [](FoveartEyeView& v) { std::swap(v.angle_left_rad, v.angle_right_rad); },
           [](FoveartEyeView& v) { v.angle_up_rad = 1.6f; }}) {
    Batch b({{10.5f, 20.5f}});
    b.batch.origins_m = nullptr;
    spoil(b.view);
    EXPECT_EQ(read(b.batch), FOVEART_RESULT_ERROR_INVALID_ARGUMENT) << fv::eye_view_problem(b.view);
  }
  {
    Batch b({{10.5f, 20.5f}});
    b.batch.origins_m = nullptr;
    b.view.size = sizeof(FoveartEyeView) - 4;
    EXPECT_EQ(read(b.batch), FOVEART_RESULT_ERROR_INVALID_ARGUMENT) << "a view too small";
  }
  FoveartRayBatch empty{};
  empty.type = FOVEART_TYPE_RAY_BATCH;
  empty.size = sizeof(FoveartRayBatch);
  EXPECT_EQ(read(empty), FOVEART_RESULT_SUCCESS) << "no rays: nothing to read";
}

// The view's rays are the explicit ones, bit for bit, over a tilted head off the origin.
TEST(RayBatchReader, ReadsTheSameRaysFromTheViewAsGivenExplicitly) {
  std::vector<glm::vec2> samples;
  for (int i = 0; i < 23; ++i) samples.emplace_back(55.3f * float(i) + 0.25f, 1440.0f - 61.7f * float(i));
  const Batch explicit_batch(samples);
  Batch view_batch(samples);
  view_batch.batch.origins_m = nullptr;
  view_batch.batch.directions = nullptr;
  fv::RayBatchReader from_rays, from_view;
  ASSERT_EQ(fv::RayBatchReader::read(&explicit_batch.batch, &from_rays), FOVEART_RESULT_SUCCESS);
  ASSERT_EQ(fv::RayBatchReader::read(&view_batch.batch, &from_view), FOVEART_RESULT_SUCCESS);
  ASSERT_EQ(from_view.size(), samples.size());
  for (std::uint32_t r = 0; r < samples.size(); ++r) {
    glm::vec3 o1, d1, o2, d2;
    ASSERT_TRUE(from_rays.ray(r, &o1, &d1)) << r;
    ASSERT_TRUE(from_view.ray(r, &o2, &d2)) << r;
    EXPECT_EQ(o1, o2) << r;
    EXPECT_EQ(d1, d2) << r;
    EXPECT_NEAR(glm::length(d1), 1.0f, 1e-6f) << r;
  }
}

TEST(RayBatchReader, NormalisesDirectionsAndRefusesRaysThatCannotBeTraced) {
  Batch b({{1.5f, 1.5f}, {2.5f, 2.5f}, {3.5f, 3.5f}, {4.5f, 4.5f}, {5.5f, 5.5f}, {6.5f, 6.5f}});
  const auto set = [&](int r, glm::vec3 o, glm::vec3 d) {
    for (int k = 0; k < 3; ++k) {
      b.origins_m[3 * r + k] = o[k];
      b.directions[3 * r + k] = d[k];
    }
  };
  set(0, glm::vec3(1.0f, 2.0f, 3.0f), glm::vec3(0.0f, -4.0f, 0.0f));
  set(1, glm::vec3(0.0f), glm::vec3(0.0f));
  set(2, glm::vec3(0.0f), glm::vec3(kNaN, 0.0f, 1.0f));
  set(3, glm::vec3(kInf, 0.0f, 0.0f), glm::vec3(0.0f, 0.0f, -1.0f));
  set(4, glm::vec3(0.0f), glm::vec3(3e30f, 0.0f, 3e30f));  // its squared length overflows
  set(5, glm::vec3(0.0f, 0.0f, 1e30f), glm::vec3(0.0f, 0.0f, -1.0f));  // Embree asserts on such an origin
  fv::RayBatchReader reader;
  ASSERT_EQ(fv::RayBatchReader::read(&b.batch, &reader), FOVEART_RESULT_SUCCESS);
  glm::vec3 o, d;
  ASSERT_TRUE(reader.ray(0, &o, &d));
  EXPECT_EQ(o, glm::vec3(1.0f, 2.0f, 3.0f));
  EXPECT_EQ(d, glm::vec3(0.0f, -1.0f, 0.0f));
  EXPECT_FALSE(reader.ray(1, &o, &d)) << "zero direction";
  EXPECT_FALSE(reader.ray(2, &o, &d)) << "NaN direction";
  EXPECT_FALSE(reader.ray(3, &o, &d)) << "infinite origin";
  EXPECT_FALSE(reader.ray(4, &o, &d)) << "overflowing direction";
  EXPECT_FALSE(reader.ray(5, &o, &d)) << "an origin beyond kMaxPositionM";
}

TEST(RayBatchReader, GivesTheDepthArrayOnlyWhereTheBatchHasRoomForIt) {
  Batch b({{1.5f, 1.5f}});
  fv::RayBatchReader reader;
  ASSERT_EQ(fv::RayBatchReader::read(&b.batch, &reader), FOVEART_RESULT_SUCCESS);
  EXPECT_EQ(reader.out_depth_m(), b.depth_m.data());
  b.batch.size = offsetof(FoveartRayBatch, out_depth_m);  // a producer built before the depth
  ASSERT_EQ(fv::RayBatchReader::read(&b.batch, &reader), FOVEART_RESULT_SUCCESS);
  EXPECT_EQ(reader.out_depth_m(), nullptr);
}
