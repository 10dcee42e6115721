// TAA in the one foveated frame while the head moves: an engine that returns
// no depth still gets its history reprojected by rotation; one that returns
// depth gets parallax-correct history (a near bar moving across a far wall as
// the eye steps sideways), reprojected or as a render cache of the rays
// themselves. Against analytic, supersampled truth.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>

#include <glm/gtc/quaternion.hpp>
#include <gtest/gtest.h>

#include "analytic_scene.hpp"
#include "foveation/display_model.hpp"
#include "foveation/foveated_view.hpp"
#include "history_kinds.hpp"

namespace foveart::foveation {
namespace {

using test::HistoryKind;

constexpr uint32_t kViewW = 96, kViewH = 80;

std::shared_ptr<const ViewTables> tables() {
  static const auto t = [] {
    PointSetKey key;
    key.display = DisplayModel::from_fov(kViewW, kViewH, 57.3);
    key.display.scale = 6.0;  // pixel grid and Poisson points both on screen
    key.seed = 1;
    InterpOptions o;
    o.method = InterpMethod::msm;
    o.k = 5;
    Executor executor(2);
    return load_view_tables(std::nullopt, key, o, executor);
  }();
  return t;
}

struct Engine {
  test::AnalyticScene scene;
  bool fill_depth = true;
};

int32_t trace(void* user, const FoveartRayBatch* batch) {
  const auto* e = static_cast<const Engine*>(user);
  const bool has_depth_field = batch->size >= FOVEART_RAY_BATCH_SIZE_WITH_DEPTH;
  for (uint32_t i = 0; i < batch->ray_count; ++i) {
    const float* o = batch->origins_m + 3 * i;
    const float* d = batch->directions + 3 * i;
    float depth = 0.0f;
    const glm::vec3 c = e->scene.shade({o[0], o[1], o[2]}, {d[0], d[1], d[2]}, &depth);
    for (int k = 0; k < 3; ++k) batch->out_rgb[3 * i + k] = c[k];
    if (e->fill_depth && has_depth_field) batch->out_depth_m[i] = depth;
  }
  return FOVEART_RESULT_SUCCESS;
}

FoveartEyeView view_at(glm::vec3 position_m, float yaw_deg) {
  EyePose pose;
  pose.position_m = position_m;
  pose.orientation = glm::angleAxis(glm::radians(-yaw_deg), glm::vec3(0, 1, 0));
  return make_eye_view(0, kViewW, kViewH, pose, -0.5f, 0.5f, 0.45f, -0.45f);
}

double rms(const ImageRgb& a, const ImageRgb& b) {
  double sq = 0.0;
  for (std::size_t i = 0; i < a.rgb.size(); ++i) sq += std::pow(double(a.rgb[i]) - double(b.rgb[i]), 2.0);
  return std::sqrt(sq / double(a.rgb.size()));
}

// Over the pixels from min_radius_px to radius_px of the gaze.
double rms(const ImageRgb& a, const ImageRgb& b, glm::vec2 gaze_px, float radius_px, float min_radius_px = 0.0f) {
  double sq = 0.0;
  std::size_t n = 0;
  for (int y = 0; y < a.height_px; ++y)
    for (int x = 0; x < a.width_px; ++x) {
      const float r = glm::length(glm::vec2(float(x) + 0.5f, float(y) + 0.5f) - gaze_px);
      if (r > radius_px || r < min_radius_px) continue;
      for (int c = 0; c < 3; ++c) sq += std::pow(double(a.at(x, y)[c]) - double(b.at(x, y)[c]), 2.0);
      n += 3;
    }
  return std::sqrt(sq / double(n));
}

constexpr glm::vec2 kGazePx{48, 40};

// The pixels the pixel grid's rays reach, a pixel inside its edge; and those
// beyond it, two pixels outside, which the gather reconstructs from Poisson points.
float pixel_grid_inside_px() { return float(tables()->key.display.pixel_grid_radius_px()) - 1.5f; }
float pixel_grid_beyond_px() { return float(tables()->key.display.pixel_grid_radius_px()) + 2.0f; }

struct MotionRun {
  int resets_after_first = 0;
  std::uint64_t with_depth = 0, disoccluded = 0;
  double final_rms = 0.0;       // TAA output against the truth, last frame
  double final_raw_rms = 0.0;   // the same rays without TAA, last frame
  double final_grid_rms = 0.0;      // ... final_rms over the pixel grid
  double final_grid_raw_rms = 0.0;  // ... final_raw_rms over the pixel grid
  double final_beyond_rms = 0.0;      // ... final_rms beyond the pixel grid
  double final_beyond_raw_rms = 0.0;  // ... final_raw_rms beyond the pixel grid
};

// frames frames, the view of frame i from view(i); a temporal history of `history`'s kind,
// new jitter each frame.
template <class ViewFn>
MotionRun run(const Engine& engine, HistoryKind history, int frames, ViewFn view, int rays_per_point = 1,
              const TemporalOptions& temporal_options = {}) {
  ViewSettings s;
  s.rays_per_point = rays_per_point;
  s.temporal_options = temporal_options;
  s.temporal = test::mode_of(history);
  s.new_jitter_each_frame = true;
  FoveatedView fv(tables(), s, test::make_history(history, *tables(), s));
  ViewSettings raw_settings = s;  // the same rays, each frame alone
  raw_settings.temporal = TemporalMode::off;
  FoveatedView raw(tables(), raw_settings);
  Executor executor(2);
  MotionRun r;
  for (int i = 0; i < frames; ++i) {
    FrameRequest req;
    req.view = view(i);
    req.gaze_px = kGazePx;
    req.frame_index = uint64_t(i + 1);
    const FrameResult res = fv.render(req, trace, const_cast<Engine*>(&engine), executor);
    EXPECT_TRUE(res.ok()) << res.message;
    EXPECT_TRUE(raw.render(req, trace, const_cast<Engine*>(&engine), executor).ok());
    if (i > 0) r.resets_after_first += res.temporal_reset ? 1 : 0;
    r.with_depth += res.history_with_depth;
    r.disoccluded += res.history_disoccluded;
    if (i == frames - 1) {
      const ImageRgb truth = engine.scene.render(req.view, 4);
      r.final_rms = rms(fv.image(), truth);
      r.final_raw_rms = rms(raw.image(), truth);
      r.final_grid_rms = rms(fv.image(), truth, kGazePx, pixel_grid_inside_px());
      r.final_grid_raw_rms = rms(raw.image(), truth, kGazePx, pixel_grid_inside_px());
      r.final_beyond_rms = rms(fv.image(), truth, kGazePx, INFINITY, pixel_grid_beyond_px());
      r.final_beyond_raw_rms = rms(raw.image(), truth, kGazePx, INFINITY, pixel_grid_beyond_px());
    }
  }
  return r;
}

TEST(TemporalMotion, EngineWithoutDepthGetsRotationalReprojection) {
  Engine engine;
  engine.scene.wall_at_infinity = true;
  engine.scene.near_bar = false;
  engine.fill_depth = false;
  auto yaw = [](int i) { return view_at({0, 1.6f, 0}, 0.5f * float(i)); };  // 35 deg/s at 70 Hz
  const MotionRun reproject = run(engine, HistoryKind::reproject, 12, yaw);
  const MotionRun restart = run(engine, HistoryKind::restart_on_view_change, 12, yaw);
  std::printf("yaw 0.5 deg/frame: RMS %.4f reprojected TAA, %.4f restarting TAA, %.4f no TAA\n", reproject.final_rms,
              restart.final_rms, reproject.final_raw_rms);
  EXPECT_EQ(reproject.resets_after_first, 0) << "the history survives the head turning";
  EXPECT_EQ(reproject.with_depth, 0u);
  EXPECT_EQ(restart.resets_after_first, 11) << "the former TAA restarts at every pose";
  EXPECT_LT(reproject.final_rms, 0.8 * reproject.final_raw_rms) << "accumulated history must beat one frame";
}

TEST(TemporalMotion, EngineWithDepthGetsParallaxCorrectHistory) {
  Engine with_depth, without_depth;
  without_depth.fill_depth = false;
  // The eye steps 2 cm right per frame: the near bar (1 m) slides ~2 px per frame across the wall (10 m).
  auto step = [](int i) { return view_at({0.02f * float(i) - 0.1f, 1.6f, 0}, 0.0f); };
  const MotionRun depth = run(with_depth, HistoryKind::reproject, 12, step);
  const MotionRun rotation = run(without_depth, HistoryKind::reproject, 12, step);
  std::printf("step 2 cm/frame: RMS %.4f with depth, %.4f rotation only, %.4f no TAA; %llu px disoccluded\n",
              depth.final_rms, rotation.final_rms, depth.final_raw_rms,
              static_cast<unsigned long long>(depth.disoccluded));
  EXPECT_EQ(depth.resets_after_first, 0);
  EXPECT_GT(depth.with_depth, 0u);
  EXPECT_GT(depth.disoccluded, 0u) << "the bar's trailing edge uncovers wall";
  EXPECT_LT(depth.final_rms, 0.7 * rotation.final_rms) << "rotation-only history ghosts the near bar";
}

// Frames of many rays blend with a larger weight (temporal_options_for_rays: the
// history holds as many rays as ten 1-ray frames). The history still beats
// one frame of the same rays while the head turns. Printed beside it: alpha
// 0.1 per frame whatever the rays, which averages more and on these smooth
// stripes comes out closer to the truth; on the default scene's fine detail
// it does not (docs/foveation.md, "Blend weight and rays per point").
TEST(TemporalMotion, FramesOfManyRaysStillBeatOneFrame) {
  Engine engine;
  engine.scene.wall_at_infinity = true;
  engine.scene.near_bar = false;
  auto yaw = [](int i) { return view_at({0, 1.6f, 0}, 0.5f * float(i)); };
  constexpr int kRays = 8;
  TemporalOptions per_frame;  // 1 - (1 - a)^8 = 0.1: alpha 0.1 per frame
  per_frame.current_weight = float(1.0 - std::pow(0.9, 1.0 / kRays));
  ASSERT_NEAR(temporal_options_for_rays(per_frame, kRays).current_weight, 0.1f, 1e-6f);
  const MotionRun per_ray = run(engine, HistoryKind::reproject, 24, yaw, kRays);
  const MotionRun frame_alpha = run(engine, HistoryKind::reproject, 24, yaw, kRays, per_frame);
  std::printf("yaw 0.5 deg/frame, %d rays per point: RMS %.4f alpha per ray, %.4f alpha 0.1 per frame, %.4f no TAA\n",
              kRays, per_ray.final_rms, frame_alpha.final_rms, per_ray.final_raw_rms);
  EXPECT_EQ(per_ray.resets_after_first, 0);
  EXPECT_LT(per_ray.final_rms, 0.8 * per_ray.final_raw_rms) << "accumulated history must beat one frame";
}

// The render cache keeps the pixel grid's rays where they hit. While the head
// turns, its rays average without blur: it beats one frame, and the
// reprojected history too. While the eye steps sideways the near bar slides
// over the wall: with the engine's depth each ray stays on its own surface,
// without it the bar's and the wall's rays smear across each other.
TEST(TemporalMotion, RayCacheKeepsParallaxCorrectRaysOverThePixelGrid) {
  Engine with_depth, without_depth;
  without_depth.fill_depth = false;
  ASSERT_GT(pixel_grid_inside_px(), 8.0f);
  auto yaw = [](int i) { return view_at({0, 1.6f, 0}, 0.5f * float(i)); };
  const MotionRun cache_yaw = run(with_depth, HistoryKind::ray_cache, 12, yaw);
  const MotionRun reproject_yaw = run(with_depth, HistoryKind::reproject, 12, yaw);
  std::printf("yaw 0.5 deg/frame, the pixel grid (%.1f px): RMS %.4f ray cache, %.4f reprojected, %.4f no TAA\n",
              double(pixel_grid_inside_px()), cache_yaw.final_grid_rms, reproject_yaw.final_grid_rms,
              cache_yaw.final_grid_raw_rms);
  EXPECT_EQ(cache_yaw.resets_after_first, 0);
  EXPECT_LT(cache_yaw.final_grid_rms, 0.5 * cache_yaw.final_grid_raw_rms) << "kept rays must beat one frame";
  EXPECT_LT(cache_yaw.final_grid_rms, reproject_yaw.final_grid_rms) << "kept rays do not blur";

  auto step = [](int i) { return view_at({0.02f * float(i) - 0.1f, 1.6f, 0}, 0.0f); };
  const MotionRun depth = run(with_depth, HistoryKind::ray_cache, 12, step);
  const MotionRun rotation = run(without_depth, HistoryKind::ray_cache, 12, step);
  std::printf("step 2 cm/frame, the pixel grid: RMS %.4f ray cache with depth, %.4f without, %.4f no TAA\n",
              depth.final_grid_rms, rotation.final_grid_rms, depth.final_grid_raw_rms);
  EXPECT_LT(depth.final_grid_rms, depth.final_grid_raw_rms);
  EXPECT_LT(depth.final_grid_rms, 0.5 * rotation.final_grid_rms) << "rays without depth smear the near bar";
}

// Beyond the pixel grid the cache filters its rays into each pixel with the
// pixel filter widened to the nearest point's disc: while the head turns and
// steps, it beats one frame and the reprojected image history there too, and
// the frame shows it there rather than the gather of this frame's points.
TEST(TemporalMotion, BeyondThePixelGridTheRayCacheFiltersIntoEachPixelAsWideAsItsPointsDisc) {
  Engine engine;
  auto move = [](int i) { return view_at({0.01f * float(i), 1.6f, 0}, 0.5f * float(i)); };
  const MotionRun cache = run(engine, HistoryKind::ray_cache, 12, move);
  const MotionRun reproject = run(engine, HistoryKind::reproject, 12, move);
  std::printf("yaw 0.5 deg/frame + 1 cm/frame, beyond the pixel grid (%.1f px): RMS %.4f ray cache, %.4f "
              "reprojected, %.4f no TAA\n",
              double(pixel_grid_beyond_px()), cache.final_beyond_rms, reproject.final_beyond_rms,
              cache.final_beyond_raw_rms);
  EXPECT_EQ(cache.resets_after_first, 0);
  EXPECT_LT(cache.final_beyond_rms, 0.6 * cache.final_beyond_raw_rms) << "kept rays must beat one frame";
  EXPECT_LT(cache.final_beyond_rms, 0.9 * reproject.final_beyond_rms) << "kept rays do not blur";

  ViewSettings s;
  s.temporal = TemporalMode::rays;
  s.new_jitter_each_frame = true;
  FoveatedView fv(tables(), s);
  Executor executor(2);
  const float beyond_px = pixel_grid_beyond_px();
  for (int i = 0; i < 3; ++i) {
    FrameRequest req;
    req.view = move(i);
    req.gaze_px = kGazePx;
    req.frame_index = uint64_t(i + 1);
    ASSERT_TRUE(fv.render(req, trace, &engine, executor).ok());
    std::size_t beyond = 0, cache_shown = 0;
    for (int y = 0; y < int(kViewH); ++y)
      for (int x = 0; x < int(kViewW); ++x) {
        if (glm::length(glm::vec2(float(x) + 0.5f, float(y) + 0.5f) - kGazePx) < beyond_px) continue;
        ++beyond;
        const bool gather = std::equal(fv.image().at(x, y), fv.image().at(x, y) + 3, fv.reconstructed().at(x, y));
        cache_shown += gather ? 0 : 1;
      }
    EXPECT_GT(beyond, 0u);
    if (i > 0) {  // the first frame's box filters miss some pixels; the next frames' rays reach them
      EXPECT_GT(double(cache_shown), 0.95 * double(beyond)) << "frame " << i;
    }
  }
}

// A saccade's onset restarts the cache with the image history (the rule
// for every history); its later flagged frames add to it again. With
// the lab's variant kept through them (RayHistoryOptions::keep_through_restarts) every ray of a still view
// stays. A blink does the same. (A Poisson point's jittered rays that land
// beyond the filter's reach of the image are not kept: a frame keeps at most
// the rays it traced.)
TEST(TemporalMotion, RayCacheRestartsOnASaccadeOrBlinkUnlessKeptThroughIt) {
  Engine engine;
  for (const bool kept : {false, true}) {
    for (const bool blink : {false, true}) {
      ViewSettings s;
      s.temporal = TemporalMode::rays;
      s.new_jitter_each_frame = true;
      const HistoryKind kind = kept ? HistoryKind::ray_cache_kept : HistoryKind::ray_cache;
      FoveatedView fv(tables(), s, test::make_history(kind, *tables(), s));
      Executor executor(2);
      std::uint64_t rays_so_far = 0;   // traced since the first frame
      std::uint64_t restart_rays = 0;  // traced on the frame the cache restarted
      for (int i = 0; i < 5; ++i) {  // flagged on frames 3 and 4
        FrameRequest req;
        req.view = view_at({0, 1.6f, 0}, 0.0f);
        req.gaze_px = kGazePx;
        req.frame_index = uint64_t(i + 1);
        req.saccade = !blink && i >= 3;
        req.blink = blink && i >= 3;
        const FrameResult result = fv.render(req, trace, &engine, executor);
        ASSERT_TRUE(result.ok());
        ASSERT_GT(result.rays, 0u);
        rays_so_far += result.rays;
        if (i == 3) {
          if (kept) {
            EXPECT_LE(fv.cached_rays(), rays_so_far);
            EXPECT_GT(double(fv.cached_rays()), 0.95 * double(rays_so_far)) << "blink " << blink;
          } else {
            EXPECT_LE(fv.cached_rays(), result.rays) << "only this frame's rays";
            EXPECT_GT(double(fv.cached_rays()), 0.95 * double(result.rays)) << "blink " << blink;
          }
        }
        if (i == 4 && !kept) {
          EXPECT_GT(fv.cached_rays(), result.rays) << "the later flagged frame adds to the restarted cache";
          EXPECT_LE(fv.cached_rays(), result.rays + restart_rays) << "and keeps nothing from before it";
        }
        if (i == 3) restart_rays = result.rays;
        EXPECT_EQ(result.temporal_reset, i == 0 || i == 3) << "frame " << i;
      }
      if (kept) {
        EXPECT_GT(double(fv.cached_rays()), 0.95 * double(rays_so_far)) << "blink " << blink;
      }
    }
  }
}

// The cache runs on the CPU path: a view that leaves reconstruction to the GPU cannot have one.
// Without CPU reconstruction the view hands a render cache elsewhere (the
// layer's GPU path) what the CPU's takes: every traced ray, once; per pixel
// the footprint (1 on the pixel grid, its point's disc beyond) and the
// covering distance of the depth test; and when to restart.
TEST(TemporalMotion, RayCacheWithoutCpuReconstructionHandsTheCacheItsRaysAndPixels) {
  ViewSettings s;
  s.temporal = TemporalMode::rays;
  s.new_jitter_each_frame = true;
  s.pixel_filter = PixelFilter::bspline2;
  s.reconstruct_on_cpu = false;
  FoveatedView view(tables(), s);
  Executor executor(2);
  const Engine engine;
  std::vector<bool> restarts;
  for (int i = 0; i < 4; ++i) {
    FrameRequest request;
    request.view = view_at({0.01f * float(i), 1.6f, 0.0f}, 0.5f * float(i));
    request.gaze_px = kGazePx;
    request.frame_index = std::uint64_t(i + 1);
    request.saccade = i == 2;
    const FrameResult r = view.render(request, trace, const_cast<Engine*>(&engine), executor);
    ASSERT_TRUE(r.ok()) << r.message;
    restarts.push_back(r.ray_cache_restart);
    std::size_t rays = 0;
    for (const auto& run : view.hand_off().traced->rays) rays += run.size();
    EXPECT_EQ(rays, r.rays) << "frame " << i;
    ASSERT_NE(view.hand_off().temporal.ray_pixels, nullptr);
    const auto& pixels = *view.hand_off().temporal.ray_pixels;
    ASSERT_EQ(pixels.size(), std::size_t(kViewW) * kViewH);
    std::size_t grid = 0, wider = 0, covering = 0;
    for (const glm::vec2& p : pixels) {
      grid += p.x == 1.0f;
      wider += p.x > 1.0f;
      covering += std::isfinite(p.y) && p.y > 0.0f;
    }
    EXPECT_GT(grid, 0u) << "the pixel grid filters at its pixels";
    EXPECT_GT(wider, 0u) << "beyond it, pixels filter as widely as their points' discs";
    EXPECT_EQ(grid + wider, pixels.size());
    EXPECT_GT(covering, pixels.size() / 2) << "the engine's depth gives most pixels a depth test";
    EXPECT_EQ(view.cached_rays(), 0u) << "the view keeps no rays itself";
  }
  EXPECT_EQ(restarts, (std::vector<bool>{true, false, true, false})) << "the first frame and the saccade restart";
}

}  // namespace
}  // namespace foveart::foveation
