// The CPU frame path of one eye with fake engines: what the callback receives,
// constants reproduced through interpolation and TAA, and the defined fallback
// for failing, throwing and NaN-returning callbacks.
#include <atomic>
#include <cmath>
#include <algorithm>
#include <cstring>
#include <functional>
#include <map>
#include <mutex>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

#include "eye_math.hpp"
#include "foveation/display_model.hpp"
#include "foveation/gaze_mapping.hpp"
#include "foveation/ray_samples.hpp"
#include "foveation/visible_points.hpp"
#include "view_pipeline.hpp"

namespace foveart::layer {
namespace {

constexpr uint32_t kW = 96;
constexpr uint32_t kH = 80;

std::shared_ptr<const ViewTables> small_tables(int k) {
  static std::mutex mutex;
  static std::map<int, std::shared_ptr<const ViewTables>> cache;
  std::lock_guard lock(mutex);
  auto& slot = cache[k];
  if (!slot) {
    foveation::PointSetKey key;
    key.display = foveation::DisplayModel::from_fov(kW, kH, 60.0);
    key.seed = 1;
    key.k = k;
    RendererSettings settings;  // Shepard; the NN test reads tap 0 of the same table
    settings.k = static_cast<uint32_t>(k);
    slot = load_view_tables(key, settings, std::nullopt);
  }
  return slot;
}

ViewRequest request_at(glm::vec2 gaze_px) {
  ViewRequest r;
  r.eye_index = 1;
  r.frame_index = 7;
  r.pose.orientation.w = 1.0f;
  r.pose.position = {0.1f, 1.6f, 0.0f};
  r.fov = {-0.5f, 0.5f, 0.45f, -0.45f};
  r.width_px = kW;
  r.height_px = kH;
  r.gaze_px = gaze_px;
  return r;
}

struct Recorder {
  std::mutex mutex;
  std::vector<uint32_t> points;
  uint64_t rays = 0;
  bool directions_unit = true;
  bool origins_at_eye = true;
  bool views_ok = true;
  float r = 0.25f, g = 0.5f, b = 0.75f;
};

int32_t constant_colour(void* user, const FoveartRayBatch* batch) {
  auto* rec = static_cast<Recorder*>(user);
  std::lock_guard lock(rec->mutex);
  rec->views_ok = rec->views_ok && batch->type == FOVEART_TYPE_RAY_BATCH && batch->size == sizeof(FoveartRayBatch) &&
                  batch->view->eye_index == 1 && batch->view->width_px == kW && batch->frame_index == 7;
  for (uint32_t i = 0; i < batch->ray_count; ++i) {
    const float* d = batch->directions + i * 3;
    rec->directions_unit = rec->directions_unit && std::fabs(std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) - 1.0f) < 1e-4f;
    rec->origins_at_eye = rec->origins_at_eye && batch->origins_m[i * 3 + 1] == 1.6f;
    rec->points.push_back(batch->point_index[i]);
    batch->out_rgb[i * 3 + 0] = rec->r;
    batch->out_rgb[i * 3 + 1] = rec->g;
    batch->out_rgb[i * 3 + 2] = rec->b;
  }
  rec->rays += batch->ray_count;
  return FOVEART_RESULT_SUCCESS;
}

int32_t always_fails(void*, const FoveartRayBatch*) { return FOVEART_RESULT_ERROR_ENGINE_FAILURE; }
int32_t always_throws(void*, const FoveartRayBatch*) { throw std::runtime_error("engine bug"); }
int32_t one_nan(void*, const FoveartRayBatch* batch) {
  for (uint32_t i = 0; i < batch->ray_count * 3; ++i) batch->out_rgb[i] = 0.5f;
  batch->out_rgb[batch->ray_count / 2] = NAN;
  return FOVEART_RESULT_SUCCESS;
}

RendererSettings settings_with(FoveartTraceRaysFn fn, void* user, XrFoveatedInterpolationFOVEART method, bool taa) {
  RendererSettings s;
  s.trace_rays = fn;
  s.user_data = user;
  s.interpolation = method;
  s.k = 5;
  s.rays_per_point = 2;
  s.taa = taa;
  return s;
}

TEST(ViewPipeline, CallbackSeesEveryVisiblePointsRaysOnce) {
  WorkerPool pool(2);
  ViewPipeline pipeline(small_tables(5));
  Recorder rec;
  std::vector<uint8_t> rgba(kW * kH * 4, 0);
  const auto out = pipeline.render(request_at({48, 40}), settings_with(&constant_colour, &rec,
                                   XR_FOVEATED_INTERPOLATION_SHEPARD_FOVEART, false), pool, rgba.data(), true);
  ASSERT_TRUE(out.ok) << out.message;
  EXPECT_GT(out.points, 0u);
  EXPECT_EQ(out.rays, out.points * 2);
  EXPECT_EQ(rec.rays, out.rays);
  EXPECT_TRUE(rec.directions_unit);
  EXPECT_TRUE(rec.origins_at_eye);
  EXPECT_TRUE(rec.views_ok);
  std::sort(rec.points.begin(), rec.points.end());
  for (std::size_t i = 0; i + 1 < rec.points.size(); i += 2) {  // each point exactly twice (2 rays)
    EXPECT_EQ(rec.points[i], rec.points[i + 1]);
    if (i + 2 < rec.points.size()) {
      EXPECT_NE(rec.points[i + 1], rec.points[i + 2]);
    }
  }
}

struct RayLog {
  std::mutex mutex;
  struct Ray {
    const uint32_t* slot;  // where the ray sits in the layer's flat arrays: gives the order
    uint32_t point;
    float sx, sy;
  };
  std::vector<Ray> rays;
};

int32_t log_rays(void* user, const FoveartRayBatch* batch) {
  auto* log = static_cast<RayLog*>(user);
  std::lock_guard lock(log->mutex);
  for (uint32_t i = 0; i < batch->ray_count; ++i) {
    log->rays.push_back({batch->point_index + i, batch->point_index[i], batch->sample_px[i * 2], batch->sample_px[i * 2 + 1]});
    for (int c = 0; c < 3; ++c) batch->out_rgb[i * 3 + c] = 0.5f;
  }
  return FOVEART_RESULT_SUCCESS;
}

// Selection split over the pool in many small chunks gives the rays of the
// core's single-threaded select_visible_points + generate_ray_samples, in order.
TEST(ViewPipeline, ChunkedSelectionEqualsTheCoreFunctionsInOrder) {
  WorkerPool pool(3);
  const auto tables = small_tables(5);
  ViewPipeline pipeline(tables, 257);
  RayLog log;
  std::vector<uint8_t> rgba(kW * kH * 4, 0);
  const auto out = pipeline.render(request_at({48, 40}), settings_with(&log_rays, &log,
                                   XR_FOVEATED_INTERPOLATION_SHEPARD_FOVEART, false), pool, rgba.data(), true);
  ASSERT_TRUE(out.ok) << out.message;
  ASSERT_GT(tables->points.size(), 4u * 257u) << "the test needs several chunks";
  std::sort(log.rays.begin(), log.rays.end(),
            [](const RayLog::Ray& a, const RayLog::Ray& b) { return std::less<const uint32_t*>()(a.slot, b.slot); });
  const auto mapping = foveation::map_gaze(kW, kH, glm::vec2(48, 40));
  const auto visible = foveation::select_visible_points(tables->points, mapping);
  const auto samples = foveation::generate_ray_samples(tables->points, visible, 2, 1);
  ASSERT_EQ(log.rays.size(), samples.size());
  for (std::size_t i = 0; i < samples.size(); ++i) {
    ASSERT_EQ(log.rays[i].point, samples.point_index[i]) << "ray " << i;
    ASSERT_EQ(log.rays[i].sx, samples.sample_px[i].x) << "ray " << i;
    ASSERT_EQ(log.rays[i].sy, samples.sample_px[i].y) << "ray " << i;
  }
}

class ConstantColour : public ::testing::TestWithParam<std::tuple<XrFoveatedInterpolationFOVEART, bool>> {};

TEST_P(ConstantColour, IsReproducedAtEveryPixel) {
  const auto [method, taa] = GetParam();
  WorkerPool pool(2);
  RendererSettings table_settings;
  table_settings.interpolation = method;
  foveation::PointSetKey key;
  key.display = foveation::DisplayModel::from_fov(kW, kH, 60.0);
  key.seed = 1;
  key.k = neighbor_count(table_settings);
  ViewPipeline pipeline(load_view_tables(key, table_settings, std::nullopt));
  Recorder rec;
  std::vector<uint8_t> rgba(kW * kH * 4, 0);
  for (int frame = 0; frame < 3; ++frame) {  // TAA accumulates over a static view
    const auto out = pipeline.render(request_at({30, 50}), settings_with(&constant_colour, &rec, method, taa), pool,
                                     rgba.data(), true);
    ASSERT_TRUE(out.ok) << out.message;
  }
  const uint8_t expected[3] = {encode_srgb8(0.25f), encode_srgb8(0.5f), encode_srgb8(0.75f)};
  for (uint32_t i = 0; i < kW * kH; ++i) {
    for (int c = 0; c < 3; ++c) ASSERT_NEAR(rgba[i * 4 + c], expected[c], 1) << "pixel " << i;
    ASSERT_EQ(rgba[i * 4 + 3], 255);
  }
}

INSTANTIATE_TEST_SUITE_P(Methods, ConstantColour,
                         ::testing::Combine(::testing::Values(XR_FOVEATED_INTERPOLATION_NEAREST_FOVEART,
                                                              XR_FOVEATED_INTERPOLATION_SHEPARD_FOVEART),
                                            ::testing::Bool()));

struct FaultCase {
  FoveartTraceRaysFn fn;
  XrFoveatedFallbackFlagsFOVEART flag;
  const char* name;
};

class Fallback : public ::testing::TestWithParam<FaultCase> {};

TEST_P(Fallback, LeavesTheImageUntouchedAndSaysWhy) {
  WorkerPool pool(2);
  ViewPipeline pipeline(small_tables(5));
  std::vector<uint8_t> rgba(kW * kH * 4, 0xAB);
  const auto out = pipeline.render(request_at({48, 40}),
                                   settings_with(GetParam().fn, nullptr, XR_FOVEATED_INTERPOLATION_SHEPARD_FOVEART, true),
                                   pool, rgba.data(), true);
  EXPECT_FALSE(out.ok);
  EXPECT_EQ(out.failure & GetParam().flag, GetParam().flag);
  EXPECT_FALSE(out.message.empty());
  EXPECT_TRUE(std::all_of(rgba.begin(), rgba.end(), [](uint8_t v) { return v == 0xAB; }));
  // The next good frame works again.
  Recorder rec;
  const auto good = pipeline.render(request_at({48, 40}), settings_with(&constant_colour, &rec,
                                    XR_FOVEATED_INTERPOLATION_SHEPARD_FOVEART, true), pool, rgba.data(), true);
  EXPECT_TRUE(good.ok);
}

INSTANTIATE_TEST_SUITE_P(
    Faults, Fallback,
    ::testing::Values(FaultCase{&always_fails, XR_FOVEATED_FALLBACK_CALLBACK_FAILED_BIT_FOVEART, "error"},
                      FaultCase{&always_throws, XR_FOVEATED_FALLBACK_CALLBACK_FAILED_BIT_FOVEART, "throw"},
                      FaultCase{&one_nan, XR_FOVEATED_FALLBACK_INVALID_COLOUR_BIT_FOVEART, "nan"}),
    [](const ::testing::TestParamInfo<FaultCase>& param_info) { return std::string(param_info.param.name); });

TEST(ViewPipeline, FailedBatchesAreCounted) {
  WorkerPool pool(2);
  ViewPipeline pipeline(small_tables(5));
  std::vector<uint8_t> rgba(kW * kH * 4, 0);
  const auto out = pipeline.render(request_at({48, 40}),
                                   settings_with(&always_fails, nullptr, XR_FOVEATED_INTERPOLATION_NEAREST_FOVEART, false),
                                   pool, rgba.data(), true);
  EXPECT_GE(out.callback_failures, 1u);
  const auto nan = pipeline.render(request_at({48, 40}),
                                   settings_with(&one_nan, nullptr, XR_FOVEATED_INTERPOLATION_NEAREST_FOVEART, false),
                                   pool, rgba.data(), true);
  EXPECT_GE(nan.invalid_colours, 1u);
}

TEST(EyeFrustum, PixelAndDirectionRoundTrip) {
  const XrFovf fov{-0.7f, 0.6f, 0.65f, -0.8f};
  const auto f = EyeFrustum::from(fov, 1280, 1440);
  for (glm::vec2 p : {glm::vec2(0, 0), glm::vec2(640.5f, 720.25f), glm::vec2(1279, 1439), glm::vec2(100, 1300)}) {
    const glm::vec2 back = f.pixel_of(f.direction_view(p));
    EXPECT_NEAR(back.x, p.x, 1e-2f);
    EXPECT_NEAR(back.y, p.y, 1e-2f);
  }
  // Lens centre of an asymmetric frustum: where -z lands, not the image centre.
  const glm::vec2 c = f.centre_px();
  EXPECT_NEAR(c.x, 1280.0f * std::tan(0.7f) / (std::tan(0.7f) + std::tan(0.6f)), 1e-2f);
  EXPECT_NEAR(c.y, 1440.0f * std::tan(0.65f) / (std::tan(0.65f) + std::tan(0.8f)), 1e-2f);
  const glm::vec3 d = f.direction_view(c);
  EXPECT_NEAR(d.z, -1.0f, 1e-5f);
}

TEST(Srgb, EncodeMatchesTheTransferFunction) {
  EXPECT_EQ(encode_srgb8(0.0f), 0);
  EXPECT_EQ(encode_srgb8(1.0f), 255);
  EXPECT_EQ(encode_srgb8(2.0f), 255);
  EXPECT_EQ(encode_srgb8(-1.0f), 0);
  EXPECT_NEAR(encode_srgb8(0.5f), 188, 1);  // 1.055 * 0.5^(1/2.4) - 0.055 = 0.7354
  EXPECT_NEAR(encode_srgb8(0.2f), 124, 1);
}

}  // namespace
}  // namespace foveart::layer
