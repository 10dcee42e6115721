// The one foveated frame with fake engines: what the callback receives,
// constants reproduced through every method and TAA, the same frame for any
// thread count, no thread started on one thread, the defined failure for
// failing, throwing and NaN-returning callbacks, a saccade restarting TAA, and
// the frame's stages (frame_stages.hpp) composed by hand and decided elsewhere.
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
#include "foveation/callback_trace.hpp"
#include "foveation/foveated_view.hpp"
#include "foveation/gather_reconstruction.hpp"
#include "foveation/host_encode.hpp"
#include "foveation/rgba8.hpp"
#include "foveation/image_history.hpp"
#include "foveation/ray_samples.hpp"
#include "foveation/visible_points.hpp"
#include "history_kinds.hpp"

namespace foveart::foveation {
namespace {

using test::HistoryKind;

constexpr uint32_t kW = 96;
constexpr uint32_t kH = 80;

// Scale 6 puts the edge of the pixel grid (~31 px from the gaze) inside the
// view, so frames hold grid and Poisson points alike.
std::shared_ptr<const ViewTables> small_tables(InterpMethod method, int k,
                                               FoveaPattern pattern = FoveaPattern::kPixelGrid) {
  static std::mutex mutex;
  static std::map<std::tuple<InterpMethod, int, FoveaPattern>, std::shared_ptr<const ViewTables>> cache;
  std::lock_guard lock(mutex);
  auto& slot = cache[{method, k, pattern}];
  if (!slot) {
    PointSetKey key;
    key.display = DisplayModel::from_fov(kW, kH, 60.0);
    key.display.scale = 6.0;
    key.display.fovea_pattern = pattern;
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

ViewSettings settings(int rays_per_point, bool temporal) {
  ViewSettings s;
  s.rays_per_point = rays_per_point;
  s.temporal = temporal ? TemporalMode::image : TemporalMode::off;
  s.new_jitter_each_frame = temporal;
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
  for (FoveaPattern pattern : {FoveaPattern::kPixelGrid, FoveaPattern::kThesisPoisson}) {
    SCOPED_TRACE(std::string(fovea_pattern_name(pattern)));
    Executor executor(3);
    const auto tables = small_tables(InterpMethod::msm, 5, pattern);
    FoveatedView view(tables, settings(2, false));
    RayLog log;
    const auto out = view.render(request_at({48, 40}), &log_rays, &log, executor);
    ASSERT_TRUE(out.ok()) << out.message;
    const auto mapping = map_gaze(kW, kH, glm::vec2(48, 40));
    const auto visible = select_visible_points(tables->points, mapping);
    const auto samples = generate_ray_samples(tables->points, visible, 2, 1, int(kW));
    ASSERT_EQ(log.rays.size(), samples.size());
    for (std::size_t i = 0; i < samples.size(); ++i) {
      const auto it = log.rays.find({samples.point_index[i], int(i % 2)});
      ASSERT_NE(it, log.rays.end()) << "ray " << i;
      ASSERT_EQ(it->second.x, samples.sample_px[i].x) << "ray " << i;
      ASSERT_EQ(it->second.y, samples.sample_px[i].y) << "ray " << i;
    }
  }
}

// In the pixel grid a pixel is its own point, traced with the full render's
// jitter (pixel_jitter) for the view's pixel filter: the same value a full
// render gives, for every method and filter.
TEST(FoveatedView, PixelGridPixelsAreExactlyTheFullRendersPixels) {
  for (PixelFilter filter : {PixelFilter::box, PixelFilter::bspline2})
  for (InterpMethod method : {InterpMethod::nearest, InterpMethod::msm, InterpMethod::rbf}) {
    SCOPED_TRACE(std::string(method_name(method)) + " " + pixel_filter_name(filter));
    Executor executor(2);
    const auto tables = small_tables(method, method == InterpMethod::nearest ? 1 : 5);
    constexpr int kSpp = 3;
    ViewSettings vs = settings(kSpp, false);
    vs.pixel_filter = filter;
    FoveatedView view(tables, vs);
    const glm::vec2 gaze(40.0f, 44.0f);
    ASSERT_TRUE(view.render(request_at(gaze), &gradient, nullptr, executor).ok());
    const auto visible = select_visible_points(tables->points, map_gaze(kW, kH, gaze));
    std::size_t grid_pixels = 0;
    for (std::size_t v = 0; v < visible.size(); ++v) {
      if (!tables->points.on_pixel_grid(visible.point_index[v])) continue;
      const glm::vec2 centre = visible.screen_px[v];
      // What the full render computes for this pixel: the mean of the callback over its samples.
      glm::vec3 sum(0.0f);
      for (int s = 0; s < kSpp; ++s) {
        const glm::vec2 p = pixel_sample_px(centre, s, 1, int(kW), filter);
        FoveartRayBatch one{};
        float rgb[3];
        one.ray_count = 1;
        one.sample_px = &p.x;
        one.out_rgb = rgb;
        gradient(nullptr, &one);
        sum += glm::vec3(rgb[0], rgb[1], rgb[2]);
      }
      sum *= 1.0f / float(kSpp);
      const float* px = view.image().at(int(centre.x), int(centre.y));
      ASSERT_EQ(px[0], sum.x) << "pixel " << centre.x << "," << centre.y;
      ASSERT_EQ(px[1], sum.y) << "pixel " << centre.x << "," << centre.y;
      ASSERT_EQ(px[2], sum.z) << "pixel " << centre.x << "," << centre.y;
      ++grid_pixels;
    }
    EXPECT_GT(grid_pixels, std::size_t(kW * kH / 4));     // the grid covers much of the view
    EXPECT_LT(grid_pixels, visible.size());               // and Poisson points the rest
  }
}

// The gaze is rounded to whole pixels and a grid pixel's rays follow the
// screen pixel, so a foveation centre drifting by fractions of a pixel (or
// whole pixels) leaves every pixel that stays inside the grid unchanged.
TEST(FoveatedView, FractionalGazeMovesDoNotShiftTheFovea) {
  Executor executor(2);
  const auto tables = small_tables(InterpMethod::msm, 5);
  FoveatedView view(tables, settings(2, false));
  const std::vector<glm::vec2> gazes{{48.0f, 40.0f}, {48.3f, 39.8f}, {48.7f, 40.45f}, {49.2f, 40.6f}, {50.6f, 41.4f}};
  const double grid_radius_px = tables->key.display.pixel_grid_radius_px();
  ASSERT_GT(grid_radius_px, 10.0);
  std::vector<std::vector<float>> frames;
  for (const glm::vec2 g : gazes) {
    ASSERT_TRUE(view.render(request_at(g), &gradient, nullptr, executor).ok());
    frames.push_back(view.image().rgb);
  }
  std::size_t compared = 0;
  for (uint32_t y = 0; y < kH; ++y) {
    for (uint32_t x = 0; x < kW; ++x) {
      // Inside the grid at every gaze (a pixel of margin for the rounding).
      bool inside = true;
      for (const glm::vec2 g : gazes) {
        inside = inside && std::hypot(double(x) + 0.5 - double(g.x), double(y) + 0.5 - double(g.y)) < grid_radius_px - 1.5;
      }
      if (!inside) continue;
      const std::size_t i = (std::size_t(y) * kW + x) * 3;
      for (std::size_t f = 1; f < frames.size(); ++f) {
        ASSERT_EQ(frames[f][i], frames[0][i]) << "pixel " << x << "," << y << " frame " << f;
        ASSERT_EQ(frames[f][i + 2], frames[0][i + 2]) << "pixel " << x << "," << y << " frame " << f;
      }
      ++compared;
    }
  }
  EXPECT_GT(compared, std::size_t(kW * kH / 8));
  // Outside the grid the Poisson points move with the gaze: those pixels do change.
  EXPECT_NE(frames.front(), frames.back());
}

class ConstantColour : public ::testing::TestWithParam<std::tuple<InterpMethod, bool>> {};

TEST_P(ConstantColour, IsReproducedAtEveryPixel) {
  const auto [method, taa] = GetParam();
  Executor executor(2);
  FoveatedView view(small_tables(method, method == InterpMethod::nearest ? 1 : 5), settings(2, taa));
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
                         ::testing::Combine(::testing::Values(InterpMethod::nearest, InterpMethod::msm,
                                                              InterpMethod::rbf),
                                            ::testing::Bool()),
                         [](const ::testing::TestParamInfo<std::tuple<InterpMethod, bool>>& p) {
                           return std::string(method_name(std::get<0>(p.param))) + (std::get<1>(p.param) ? "_taa" : "");
                         });

// Bit for bit the same frame (with TAA over a gaze move) on 1, 2 and 3 threads.
TEST(FoveatedView, SameFramesForAnyThreadCount) {
  std::vector<std::vector<float>> frames;
  for (unsigned threads : {1u, 2u, 3u}) {
    Executor executor(threads);
    FoveatedView view(small_tables(InterpMethod::rbf, 5), settings(3, true));
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

// threads = 1: every stage (callback, gather, TAA) on the caller, and no
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

// The temporal blend weighs a frame of n rays per point as n one-ray frames (temporal_blend.hpp);
// the GPU path reads the same options (tests/gpu/reconstruction_test.cpp).
TEST(FoveatedView, TaaBlendWeightFollowsTheRaysPerPoint) {
  for (int rays : {1, 4, 16}) {
    const FoveatedView view(small_tables(InterpMethod::msm, 5), settings(rays, true));
    const float expected = temporal_options_for_rays(TemporalOptions{}, rays).current_weight;
    EXPECT_EQ(view.temporal_options().current_weight, expected) << rays << " rays";
    EXPECT_EQ(view.settings().temporal_options.current_weight, TemporalOptions{}.current_weight) << "the settings stay as given";
  }
  EXPECT_NEAR(temporal_options_for_rays(TemporalOptions{}, 4).current_weight, 1.0 - std::pow(0.9, 4), 1e-6);
}

TEST(FoveatedView, SaccadeRestartsTheHistory) {
  Executor executor(2);
  FoveatedView view(small_tables(InterpMethod::msm, 5), settings(1, true));
  auto request = request_at({48, 40});
  EXPECT_TRUE(view.render(request, &gradient, nullptr, executor).temporal_reset);  // first frame
  request.frame_index = 8;
  EXPECT_FALSE(view.render(request, &gradient, nullptr, executor).temporal_reset);  // steady: the history goes on
  request.frame_index = 9;
  request.saccade = true;  // same gaze pixel, but the provider saw a saccade
  EXPECT_TRUE(view.render(request, &gradient, nullptr, executor).temporal_reset);
  request.frame_index = 10;  // still flagged: the history restarted at the onset and accumulates again
  EXPECT_FALSE(view.render(request, &gradient, nullptr, executor).temporal_reset);
  request.frame_index = 11;
  request.saccade = false;
  EXPECT_FALSE(view.render(request, &gradient, nullptr, executor).temporal_reset);
  request.frame_index = 12;
  request.blink = true;  // a new flagged run: its first frame restarts
  EXPECT_TRUE(view.render(request, &gradient, nullptr, executor).temporal_reset);
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
  EXPECT_TRUE(again.temporal_reset);
}

INSTANTIATE_TEST_SUITE_P(Faults, Failure,
                         ::testing::Values(FaultCase{&always_fails, FrameFailure::callback_failed, "error"},
                                           FaultCase{&always_throws, FrameFailure::callback_failed, "throw"},
                                           FaultCase{&one_nan, FrameFailure::invalid_colour, "nan"}),
                         [](const ::testing::TestParamInfo<FaultCase>& param_info) { return std::string(param_info.param.name); });

TEST(FoveatedView, FailedBatchesAndInvalidColoursAreCounted) {
  Executor executor(2);
  FoveatedView view(small_tables(InterpMethod::nearest, 1), settings(1, false));
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

// The stages composed by hand (frame_stages.hpp) are the view's frame, bit
// for bit: the view adds nothing between them.
TEST(FrameStages, ComposedByHandTheyAreTheViewsFrame) {
  Executor executor(2);
  const auto tables = small_tables(InterpMethod::msm, 5);
  ViewSettings s = settings(2, true);
  s.centre_deadband_deg = 0.0;  // the centre is the gaze: no FoveationCentre needed below
  FoveatedView view(tables, s);
  CallbackTrace trace(tables->points, s.rays_per_point, s.pixel_filter, s.new_jitter_each_frame, false);
  GatherReconstruction reconstruct(*tables, s.rbf_clamp);
  ImageHistory history(tables->neighbors, temporal_options_for_rays(s.temporal_options, s.rays_per_point), true);
  HostEncode encode;
  HostFrame host;
  for (int f = 0; f < 4; ++f) {
    FrameRequest request = request_at({40.0f + 3.0f * float(f), 38});
    request.frame_index = uint64_t(f + 1);
    request.view.position_m[0] += 0.002f * float(f);  // the history is reprojected
    ASSERT_TRUE(view.render(request, &gradient, nullptr, executor).ok());
    FrameContext frame;
    frame.view = request.view;
    frame.mapping = map_gaze(int(kW), int(kH), request.gaze_px);
    frame.frame_index = request.frame_index;
    frame.sample_seed = s.sample_seed + request.frame_index;
    frame.trace_rays = &gradient;
    ASSERT_TRUE(trace.trace(frame, host, executor).ok());
    GatherStats gathered;
    std::string error;
    ASSERT_TRUE(reconstruct.reconstruct(frame, trace.traced(), host, executor, &gathered, &error)) << error;
    TemporalFrame decision;
    ASSERT_TRUE(history.apply(frame, trace.traced(), host, executor, &decision, &error)) << error;
    EXPECT_EQ(host.reconstructed.rgb, view.reconstructed().rgb) << "frame " << f;
    ASSERT_NE(host.output, nullptr);
    EXPECT_EQ(host.output->rgb, view.image().rgb) << "frame " << f;
    EXPECT_EQ(decision.reset, f == 0) << "frame " << f;
    std::vector<std::uint8_t> by_hand(std::size_t(kW) * kH * 4), by_view(by_hand.size());
    host.rgba8 = by_hand.data();
    ASSERT_TRUE(encode.encode(frame, host, executor, &error)) << error;
    host.rgba8 = nullptr;
    encode_rgba8(view.image(), true, DisplayTransform{}, by_view.data(), executor);
    EXPECT_EQ(by_hand, by_view) << "frame " << f;
  }
}

// The CPU's stages on resources that are not the host's: a clear error, a
// failed frame the view reports, and nothing written.
TEST(FrameStages, HostStagesRefuseResourcesOfAnotherSide) {
  struct NotTheHost final : FrameResources {};
  Executor executor(2);
  const auto tables = small_tables(InterpMethod::msm, 5);
  FoveatedView view(tables, settings(1, true));
  NotTheHost elsewhere;
  const FrameResult result = view.render(request_at({48, 40}), &gradient, nullptr, elsewhere, executor);
  EXPECT_EQ(result.failure, FrameFailure::resources_failed);
  EXPECT_NE(result.message.find("on the host"), std::string::npos) << result.message;
  EXPECT_EQ(view.image().width_px, 0) << "no image was made";
  std::string error;
  EXPECT_FALSE(HostEncode().encode(FrameContext{}, elsewhere, executor, &error));
  EXPECT_NE(error.find("encode"), std::string::npos) << error;
  ASSERT_TRUE(view.render(request_at({48, 40}), &gradient, nullptr, executor).ok()) << "the host's frame still runs";
}

// A history's decision for a frame reconstructed elsewhere (the GPU path)
// is the one it applies here: the same restarts, blend weights and ray-cache
// restarts over moves, a saccade and a gaze jump, for every history.
TEST(FrameStages, DecideAgreesWithAccumulateForEveryHistory) {
  for (const HistoryKind kind : {HistoryKind::restart_on_view_change, HistoryKind::reproject, HistoryKind::ray_cache}) {
    SCOPED_TRACE(int(kind));
    Executor executor(2);
    ViewSettings s = settings(1, true);
    s.temporal = test::mode_of(kind);
    const auto tables = small_tables(InterpMethod::msm, 5);
    FoveatedView here(tables, s, test::make_history(kind, *tables, s));
    s.reconstruct_on_cpu = false;
    FoveatedView elsewhere(tables, s, test::make_history(kind, *tables, s));
    std::vector<bool> resets;
    for (int f = 0; f < 8; ++f) {
      FrameRequest request = request_at(f == 6 ? glm::vec2(8, 8) : glm::vec2(48, 40));  // frame 6 jumps 51 px
      request.frame_index = uint64_t(f + 1);
      request.saccade = f == 3;
      if (f >= 4) request.view.position_m[0] += 0.001f * float(f);  // the head moves from frame 4 on
      const FrameResult a = here.render(request, &gradient, nullptr, executor);
      const FrameResult b = elsewhere.render(request, &gradient, nullptr, executor);
      ASSERT_TRUE(a.ok() && b.ok());
      const TemporalFrame& x = here.hand_off().temporal;
      const TemporalFrame& y = elsewhere.hand_off().temporal;
      EXPECT_EQ(x.reset, y.reset) << "frame " << f;
      EXPECT_EQ(x.blend.current_weight, y.blend.current_weight) << "frame " << f;
      EXPECT_EQ(x.ray_restart, y.ray_restart) << "frame " << f;
      EXPECT_EQ(a.temporal_reset, b.temporal_reset) << "frame " << f;
      resets.push_back(x.reset);
    }
    EXPECT_TRUE(resets[0]) << "the first frame starts the history";
    EXPECT_TRUE(resets[3]) << "the saccade's onset restarts it";
    EXPECT_TRUE(resets[6]) << "the gaze jump restarts it";
    EXPECT_FALSE(resets[1]);
    EXPECT_EQ(resets[5], kind == HistoryKind::restart_on_view_change) << "a moved head restarts only that history";
  }
}

}  // namespace
}  // namespace foveart::foveation
