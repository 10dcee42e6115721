// The one foveated frame with fake engines: what the callback receives,
// constants reproduced through every method and TAA, the same frame for any
// thread count, no thread started on one thread, the defined failure for
// failing, throwing and NaN-returning callbacks, and a saccade restarting TAA.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <dirent.h>
#include <map>
#include <mutex>
#include <stdexcept>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "foveation/display_model.hpp"
#include "foveation/foveated_view.hpp"
#include "foveation/ray_samples.hpp"
#include "foveation/visible_points.hpp"

namespace foveart::foveation {
namespace {

constexpr uint32_t kW = 96;
constexpr uint32_t kH = 80;

std::shared_ptr<const ViewTables> small_tables(InterpMethod method, int k) {
  static std::mutex mutex;
  static std::map<std::pair<InterpMethod, int>, std::shared_ptr<const ViewTables>> cache;
  std::lock_guard lock(mutex);
  auto& slot = cache[{method, k}];
  if (!slot) {
    PointSetKey key;
    key.display = DisplayModel::from_fov(kW, kH, 60.0);
    key.seed = 1;
    InterpOptions o;
    o.method = method;
    o.k = k;
    Executor executor(2);
    slot = load_view_tables(std::nullopt, key, o, executor);
  }
  return slot;
}

FrameRequest request_at(glm::vec2 gaze_px) {
  FrameRequest r;
  EyePose pose;
  pose.position_m = {0.1f, 1.6f, 0.0f};
  r.view = make_eye_view(1, kW, kH, pose, -0.5f, 0.5f, 0.45f, -0.45f);
  r.frame_index = 7;
  r.gaze_px = gaze_px;
  return r;
}

ViewSettings settings(int rays_per_point, bool taa) {
  ViewSettings s;
  s.rays_per_point = rays_per_point;
  s.taa = taa;
  s.new_jitter_each_frame = taa;
  return s;
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
// A colour that depends on where the ray goes, so frames can be compared.
int32_t gradient(void*, const FoveartRayBatch* batch) {
  for (uint32_t i = 0; i < batch->ray_count; ++i) {
    // Points in the 10 px margin beyond the screen are traced too: keep colours >= 0 there.
    batch->out_rgb[i * 3 + 0] = (batch->sample_px[i * 2] + 20.0f) / float(kW + 40);
    batch->out_rgb[i * 3 + 1] = (batch->sample_px[i * 2 + 1] + 20.0f) / float(kH + 40);
    batch->out_rgb[i * 3 + 2] = 0.5f + 0.5f * std::sin(batch->sample_px[i * 2] * 0.3f);
  }
  return FOVEART_RESULT_SUCCESS;
}

TEST(FoveatedView, CallbackSeesEveryVisiblePointsRaysOnce) {
  Executor executor(2);
  FoveatedView view(small_tables(InterpMethod::msm, 5), settings(2, false));
  Recorder rec;
  const auto out = view.render(request_at({48, 40}), &constant_colour, &rec, executor);
  ASSERT_TRUE(out.ok()) << out.message;
  EXPECT_GT(out.points, 0u);
  EXPECT_EQ(out.rays, uint64_t{out.points} * 2);
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
  std::map<std::pair<uint32_t, int>, glm::vec2> rays;  // (point, n-th ray of it) -> sample
  std::map<uint32_t, int> seen;
};

int32_t log_rays(void* user, const FoveartRayBatch* batch) {
  auto* log = static_cast<RayLog*>(user);
  std::lock_guard lock(log->mutex);
  for (uint32_t i = 0; i < batch->ray_count; ++i) {
    const uint32_t p = batch->point_index[i];
    log->rays[{p, log->seen[p]++}] = {batch->sample_px[i * 2], batch->sample_px[i * 2 + 1]};
    for (int c = 0; c < 3; ++c) batch->out_rgb[i * 3 + c] = 0.5f;
  }
  return FOVEART_RESULT_SUCCESS;
}

// The fused pass traces exactly the rays of the core's select_visible_points +
// generate_ray_samples: the same points, the same sample positions.
TEST(FoveatedView, TracesTheRaysOfTheCoreSelectionAndSamples) {
  Executor executor(3);
  const auto tables = small_tables(InterpMethod::msm, 5);
  FoveatedView view(tables, settings(2, false));
  RayLog log;
  const auto out = view.render(request_at({48, 40}), &log_rays, &log, executor);
  ASSERT_TRUE(out.ok()) << out.message;
  const auto mapping = map_gaze(kW, kH, glm::vec2(48, 40));
  const auto visible = select_visible_points(tables->points, mapping);
  const auto samples = generate_ray_samples(tables->points, visible, 2, 1);
  ASSERT_EQ(log.rays.size(), samples.size());
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const auto it = log.rays.find({samples.point_index[i], int(i % 2)});
    ASSERT_NE(it, log.rays.end()) << "ray " << i;
    ASSERT_EQ(it->second.x, samples.sample_px[i].x) << "ray " << i;
    ASSERT_EQ(it->second.y, samples.sample_px[i].y) << "ray " << i;
  }
}

class ConstantColour : public ::testing::TestWithParam<std::tuple<InterpMethod, bool>> {};

TEST_P(ConstantColour, IsReproducedAtEveryPixel) {
  const auto [method, taa] = GetParam();
  Executor executor(2);
  FoveatedView view(small_tables(method, method == InterpMethod::nn ? 1 : 5), settings(2, taa));
  Recorder rec;
  rec.r = 0.2f;
  for (int frame = 0; frame < 3; ++frame) {  // TAA accumulates over a static view
    auto request = request_at({30, 50});
    const auto out = view.render(request, &constant_colour, &rec, executor);
    ASSERT_TRUE(out.ok()) << out.message;
  }
  const ImageRgb& image = view.image();
  ASSERT_EQ(image.width_px, int(kW));
  ASSERT_EQ(image.height_px, int(kH));
  for (std::size_t i = 0; i < image.pixel_count(); ++i) {
    ASSERT_NEAR(image.rgb[i * 3 + 0], 0.2f, 1e-3f) << "pixel " << i;
    ASSERT_NEAR(image.rgb[i * 3 + 1], 0.5f, 1e-3f) << "pixel " << i;
    ASSERT_NEAR(image.rgb[i * 3 + 2], 0.75f, 1e-3f) << "pixel " << i;
  }
}

INSTANTIATE_TEST_SUITE_P(Methods, ConstantColour,
                         ::testing::Combine(::testing::Values(InterpMethod::nn, InterpMethod::msm, InterpMethod::rbf_mq),
                                            ::testing::Bool()));

// Bit for bit the same frame (with TAA over a gaze move) on 1, 2 and 3 threads.
TEST(FoveatedView, SameFramesForAnyThreadCount) {
  std::vector<std::vector<float>> frames;
  for (unsigned threads : {1u, 2u, 3u}) {
    Executor executor(threads);
    FoveatedView view(small_tables(InterpMethod::rbf_mq, 5), settings(3, true));
    std::vector<float> all;
    for (int f = 0; f < 3; ++f) {
      auto request = request_at({40.0f + 4.0f * float(f), 38});
      request.frame_index = uint64_t(f);
      ASSERT_TRUE(view.render(request, &gradient, nullptr, executor).ok());
      all.insert(all.end(), view.image().rgb.begin(), view.image().rgb.end());
    }
    frames.push_back(std::move(all));
  }
  EXPECT_EQ(frames[0], frames[1]);
  EXPECT_EQ(frames[0], frames[2]);
}

std::size_t process_threads() {
  std::size_t n = 0;
  if (DIR* d = opendir("/proc/self/task")) {
    while (const dirent* e = readdir(d)) n += e->d_name[0] != '.';
    closedir(d);
  }
  return n;
}

struct ThreadProbe {
  std::mutex mutex;
  std::thread::id caller = std::this_thread::get_id();
  bool other_thread = false;
  std::size_t max_threads = 0;
};

int32_t probe_threads(void* user, const FoveartRayBatch* batch) {
  auto* probe = static_cast<ThreadProbe*>(user);
  std::lock_guard lock(probe->mutex);
  probe->other_thread = probe->other_thread || std::this_thread::get_id() != probe->caller;
  probe->max_threads = std::max(probe->max_threads, process_threads());
  for (uint32_t i = 0; i < batch->ray_count * 3; ++i) batch->out_rgb[i] = 0.5f;
  return FOVEART_RESULT_SUCCESS;
}

// worker_threads = 1: every stage (callback, gather, TAA) on the caller, and no
// thread started anywhere in the frame.
TEST(FoveatedView, OneThreadRunsEveryStageOnTheCallerAndStartsNoThread) {
  const auto tables = small_tables(InterpMethod::msm, 5);
  Executor executor(1);
  EXPECT_EQ(executor.thread_count(), 1u);
  FoveatedView view(tables, settings(2, true));
  const std::size_t before = process_threads();
  ThreadProbe probe;
  for (int f = 0; f < 3; ++f) {
    auto request = request_at({48, 40});
    request.frame_index = uint64_t(f);
    ASSERT_TRUE(view.render(request, &probe_threads, &probe, executor).ok());
  }
  EXPECT_FALSE(probe.other_thread);
  EXPECT_EQ(probe.max_threads, before);
  EXPECT_EQ(process_threads(), before);
}

TEST(FoveatedView, SaccadeRestartsTheHistory) {
  Executor executor(2);
  FoveatedView view(small_tables(InterpMethod::msm, 5), settings(1, true));
  auto request = request_at({48, 40});
  EXPECT_TRUE(view.render(request, &gradient, nullptr, executor).taa_reset);  // first frame
  request.frame_index = 8;
  EXPECT_FALSE(view.render(request, &gradient, nullptr, executor).taa_reset);  // steady: the history goes on
  request.frame_index = 9;
  request.saccade = true;  // same gaze pixel, but the provider saw a saccade
  EXPECT_TRUE(view.render(request, &gradient, nullptr, executor).taa_reset);
  request.frame_index = 10;
  request.saccade = false;
  EXPECT_FALSE(view.render(request, &gradient, nullptr, executor).taa_reset);
}

struct FaultCase {
  FoveartTraceRaysFn fn;
  FrameFailure failure;
  const char* name;
};

class Failure : public ::testing::TestWithParam<FaultCase> {};

TEST_P(Failure, KeepsTheLastGoodImageAndSaysWhy) {
  Executor executor(2);
  FoveatedView view(small_tables(InterpMethod::msm, 5), settings(1, true));
  Recorder rec;
  ASSERT_TRUE(view.render(request_at({48, 40}), &constant_colour, &rec, executor).ok());
  const std::vector<float> good = view.image().rgb;
  const auto out = view.render(request_at({48, 40}), GetParam().fn, nullptr, executor);
  EXPECT_FALSE(out.ok());
  EXPECT_EQ(out.failure, GetParam().failure);
  EXPECT_FALSE(out.message.empty());
  EXPECT_EQ(view.image().rgb, good);
  // The next good frame works again, and restarts the history.
  const auto again = view.render(request_at({48, 40}), &constant_colour, &rec, executor);
  EXPECT_TRUE(again.ok());
  EXPECT_TRUE(again.taa_reset);
}

INSTANTIATE_TEST_SUITE_P(Faults, Failure,
                         ::testing::Values(FaultCase{&always_fails, FrameFailure::callback_failed, "error"},
                                           FaultCase{&always_throws, FrameFailure::callback_failed, "throw"},
                                           FaultCase{&one_nan, FrameFailure::invalid_colour, "nan"}),
                         [](const ::testing::TestParamInfo<FaultCase>& param_info) { return std::string(param_info.param.name); });

TEST(FoveatedView, FailedBatchesAndInvalidColoursAreCounted) {
  Executor executor(2);
  FoveatedView view(small_tables(InterpMethod::nn, 1), settings(1, false));
  EXPECT_GE(view.render(request_at({48, 40}), &always_fails, nullptr, executor).failed_batches, 1u);
  EXPECT_GE(view.render(request_at({48, 40}), &one_nan, nullptr, executor).invalid_colours, 1u);
}

TEST(FoveatedView, RejectsAViewThatDoesNotFitItsTables) {
  Executor executor(1);
  FoveatedView view(small_tables(InterpMethod::msm, 5), settings(1, false));
  auto request = request_at({48, 40});
  request.view.width_px = kW + 1;
  EXPECT_THROW(view.render(request, &gradient, nullptr, executor), std::invalid_argument);
  EXPECT_THROW(view.render(request_at({48, 40}), nullptr, nullptr, executor), std::invalid_argument);
}

}  // namespace
}  // namespace foveart::foveation
