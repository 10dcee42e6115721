// Rays per point by the content (point_rays.hpp, point_ray_count; ContentDensityOptions::
// rays_contrast): the rule's shares, and in frames: a point beside an edge casts what the rule
// gives for its disc (all of them from a disc one pixel in radius), a point in a flat or dark
// tile one ray, the pixel-exact fovea all of them, the first frame what the discs give, and the frame
// stays whole (every visible point coloured, the flat parts unchanged); with the contrast doubling
// by eccentricity (rays_doubling_ecc_deg), its steps where the eccentricity says and, in frames,
// the points beyond them cast what the doubled contrast gives.
#include <algorithm>
#include <cmath>
#include <iostream>
#include <mutex>
#include <numbers>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "foveation/content_density.hpp"
#include "foveation/display_model.hpp"
#include "foveation/foveated_view.hpp"
#include "foveation/point_rays.hpp"
#include "foveation/visible_points.hpp"
#include "threaded/small_view.hpp"

namespace foveart::foveation::point_ray_count_test {
namespace {

constexpr uint32_t kRaysW = 128;
constexpr uint32_t kRaysH = 96;
constexpr float kRaysEdgeX = 16.0f;  // a tile border (16 px tiles), left of the pixel grid
constexpr int kRays = 8;
constexpr float kRaysContrast = 0.2f;

// Scale 8: a pixel grid about 22 px in radius around the centre, Poisson points around it.
std::shared_ptr<const ViewTables> ray_tables() {
  static const std::shared_ptr<const ViewTables> t =
      small_view::tables(kRaysW, kRaysH, 8.0, 5, InterpMethod::nearest, 1);
  return t;
}

FrameRequest ray_request(uint64_t frame_index) { return small_view::request(kRaysW, kRaysH, frame_index); }

ViewSettings ray_settings(float rays_contrast) {
  ViewSettings s = temporal_view_settings(TemporalMode::off, kRays, 1);
  s.content_density.rays_contrast = rays_contrast;
  return s;
}

// The engine: a scene by screen position, counting the rays each point was given.
struct RayScene {
  float left = 0.02f, right = 1.0f;  // left of kRaysEdgeX, right of it
  std::mutex mutex;
  std::vector<uint32_t> rays_of_point;
};

int32_t count_rays(void* user, const FoveartRayBatch* batch) {
  auto* scene = static_cast<RayScene*>(user);
  std::lock_guard lock(scene->mutex);
  for (uint32_t i = 0; i < batch->ray_count; ++i) {
    const float v = batch->sample_px[i * 2] < kRaysEdgeX ? scene->left : scene->right;
    for (int c = 0; c < 3; ++c) batch->out_rgb[i * 3 + c] = v;
    ++scene->rays_of_point[batch->point_index[i]];
  }
  return FOVEART_RESULT_SUCCESS;
}

FrameResult render_counting(FoveatedView& view, RayScene& scene, uint64_t frame_index, Executor& executor,
                            const ViewTables& tables = *ray_tables()) {
  scene.rays_of_point.assign(tables.points.size(), 0);
  return view.render(ray_request(frame_index), &count_rays, &scene, executor);
}

TEST(PointRayCount, SharesOfDiscAndContrast) {
  EXPECT_EQ(point_ray_count(32, 2.0f, 0.5f, 0.2f), 32u) << "a wide disc at high contrast: all";
  EXPECT_EQ(point_ray_count(32, 1.0f, 0.2f, 0.2f), 32u) << "a disc one pixel in radius: all";
  EXPECT_EQ(point_ray_count(32, 0.5f, 1.0f, 0.2f), 8u) << "a disc of a quarter of that area: a quarter";
  EXPECT_EQ(point_ray_count(32, 2.0f, 0.1f, 0.2f), 8u) << "half the contrast: a quarter (standard error)";
  EXPECT_EQ(point_ray_count(32, 2.0f, 0.0f, 0.2f), 1u) << "a flat tile: one ray";
  EXPECT_EQ(point_ray_count(32, 2.0f, INFINITY, 0.2f), 32u) << "no contrast measured yet: all";
  EXPECT_EQ(point_ray_count(1, 0.1f, 0.0f, 0.2f), 1u);
  // More contrast never gives fewer rays, a wider disc never fewer.
  for (float c = 0.0f; c < 0.3f; c += 0.01f) {
    EXPECT_LE(point_ray_count(16, 3.0f, c, 0.2f), point_ray_count(16, 3.0f, c + 0.01f, 0.2f)) << c;
    EXPECT_LE(point_ray_count(16, 0.1f + c, 1.0f, 0.2f), point_ray_count(16, 0.11f + c, 1.0f, 0.2f)) << c;
  }
}

TEST(PointRayCount, ContrastDoublesAtEachEccentricityStep) {
  constexpr double kViewDistancePx = 500.0;
  const auto distance_px = [&](double ecc_deg) {
    return float(kViewDistancePx * std::tan(ecc_deg * std::numbers::pi / 180.0));
  };
  const RaysContrastSteps off = rays_contrast_steps(0.2f, 0.0f, kViewDistancePx);
  EXPECT_EQ(off.at(0.0f, 0.0f), 0.2f);
  EXPECT_EQ(off.at(1e5f, 1e5f), 0.2f) << "no steps: the same contrast everywhere";

  const RaysContrastSteps thirty = rays_contrast_steps(0.2f, 30.0f, kViewDistancePx);
  EXPECT_NEAR(std::sqrt(thirty.distance_sq_px2[0]), distance_px(30.0), 1e-3f);
  EXPECT_NEAR(std::sqrt(thirty.distance_sq_px2[1]), distance_px(60.0), 1e-2f);
  EXPECT_TRUE(std::isinf(thirty.distance_sq_px2[2])) << "90 degrees and beyond: no step";
  EXPECT_EQ(thirty.at(distance_px(29.9), 0.0f), 0.2f);
  EXPECT_EQ(thirty.at(0.0f, distance_px(30.1)), 0.4f) << "any direction from the gaze";
  EXPECT_EQ(thirty.at(distance_px(45.0) * 0.6f, distance_px(45.0) * 0.8f), 0.4f);
  EXPECT_EQ(thirty.at(distance_px(61.0), 0.0f), 0.8f);

  const RaysContrastSteps twenty = rays_contrast_steps(0.2f, 20.0f, kViewDistancePx);
  for (int k = 0; k < kRaysContrastSteps; ++k)
    EXPECT_NEAR(std::sqrt(twenty.distance_sq_px2[std::size_t(k)]) / distance_px(20.0 * (k + 1)), 1.0f, 1e-5f) << k;
  EXPECT_EQ(twenty.at(distance_px(85.0), 0.0f), 3.2f) << "at most four doublings";
}

TEST(PointRayCount, FramesGiveEdgesTheirRaysAndFlatOrDarkTilesOne) {
  Executor executor(2);
  RayScene varied, full;
  FoveatedView view(ray_tables(), ray_settings(kRaysContrast)), reference(ray_tables(), ray_settings(0.0f));
  const FrameResult first = render_counting(view, varied, 1, executor);
  ASSERT_TRUE(first.ok()) << first.message;
  ASSERT_TRUE(render_counting(reference, full, 1, executor).ok());
  const PointSet& points = ray_tables()->points;
  // No contrast measured yet: a point casts what its disc calls for, a grid point all.
  uint64_t first_rays = 0;
  for (uint32_t id = 0; id < points.size(); ++id) {
    const uint32_t rays = varied.rays_of_point[id];
    first_rays += rays;
    if (rays == 0) continue;
    const uint32_t expected =
        points.on_pixel_grid(id) ? uint32_t(kRays) : point_ray_count(kRays, points.radius_px[id], INFINITY, kRaysContrast);
    ASSERT_EQ(rays, expected) << "first frame, point " << id;
  }
  EXPECT_EQ(first.rays, first_rays);
  EXPECT_LT(first.rays, first.points * uint64_t(kRays)) << "the discs under a pixel in radius cast fewer";
  const FrameResult second = render_counting(view, varied, 2, executor);
  ASSERT_TRUE(second.ok()) << second.message;
  ASSERT_TRUE(render_counting(reference, full, 2, executor).ok());

  const VisiblePoints visible = select_visible_points(points, map_gaze(kRaysW, kRaysH, second.centre_px));
  uint64_t counted = 0;
  std::size_t edge_points = 0, flat_points = 0, grid_points = 0;
  for (std::size_t v = 0; v < visible.size(); ++v) {
    const uint32_t id = visible.point_index[v];
    const uint32_t rays = varied.rays_of_point[id];
    counted += rays;
    ASSERT_EQ(full.rays_of_point[id], uint32_t(kRays)) << "off: point " << id;
    if (points.on_pixel_grid(id)) {
      ++grid_points;
      EXPECT_EQ(rays, uint32_t(kRays)) << "grid point " << id << ": the pixel-exact fovea keeps its rays";
      continue;
    }
    const float x = visible.screen_px[v].x;
    if (x >= kRaysEdgeX - 16.0f && x < kRaysEdgeX + 16.0f) {  // the tiles beside the edge: contrast 0.94
      ++edge_points;
      EXPECT_EQ(rays, point_ray_count(kRays, points.radius_px[id], 1.0f, kRaysContrast)) << "point " << id;
    } else if (x < kRaysEdgeX - 32.0f || x >= kRaysEdgeX + 32.0f) {  // flat tiles, their neighbours flat too
      ++flat_points;
      EXPECT_EQ(rays, 1u) << "point " << id << " at x = " << x << " in a flat tile";
    }
  }
  ASSERT_GT(edge_points, 50u);
  ASSERT_GT(flat_points, 200u);
  ASSERT_GT(grid_points, 0u);
  EXPECT_EQ(second.rays, counted) << "the stats count the rays handed to the engine";
  const TracedPoints& traced = *view.hand_off().traced;
  for (uint32_t id = 0; id < points.size(); ++id)
    ASSERT_EQ(traced.rays_cast[id], varied.rays_of_point[id]) << "the trace's record of point " << id << "'s rays";
  EXPECT_GT(second.density.test_ms, 0.0) << "a point's rays by its tile's contrast are density's per-point test";
  EXPECT_LT(double(second.rays), 0.7 * double(first.rays));
  std::cout << "[ measured ] rays of the second frame: " << second.rays << " of " << first.rays << " ("
            << second.points << " points)\n";
  // The frame is whole: every visible point coloured; a flat tile's one ray is its colour.
  EXPECT_EQ(second.points, first.points);
  const ImageRgb& a = view.image();
  const ImageRgb& b = reference.image();
  for (uint32_t y = 0; y < kRaysH; ++y)
    for (uint32_t x = 0; x < kRaysW; ++x) {
      const float* pa = a.at(int(x), int(y));
      ASSERT_TRUE(std::isfinite(pa[0])) << x << "," << y;
      if (std::fabs(float(x) + 0.5f - kRaysEdgeX) > 24.0f) {
        ASSERT_NEAR(pa[0], b.at(int(x), int(y))[0], 1e-6f) << x << "," << y;
      }
    }
}

// A scale below 1 widens the pixel grid beyond the pixel-exact fovea (the grid of the
// thesis's density). That margin keeps every point, as the thinning never takes a grid
// point, but its rays follow the content as a Poisson point's of the same disc (a pixel's
// area) do: a few beside the edge, one in a flat tile. The exact fovea keeps them all.
TEST(PointRayCount, TheGridMarginOfADenserScaleCastsByContentTheExactFoveaAll) {
  const auto tables = small_view::grid_margin_tables(kRaysW, kRaysH, InterpMethod::nearest, 1);
  const PointSet& points = tables->points;
  const double exact_px = tables->key.display.exact_fovea_radius_px();
  ASSERT_LT(exact_px + 8.0, tables->key.display.pixel_grid_radius_px()) << "the scale leaves a margin";
  Executor executor(2);
  ViewSettings settings = ray_settings(kRaysContrast);
  settings.content_density.full_contrast = 0.5f;  // and thinning, which leaves the whole grid traced
  FoveatedView view(tables, settings);
  RayScene scene;
  ASSERT_TRUE(render_counting(view, scene, 1, executor, *tables).ok());
  const FrameResult second = render_counting(view, scene, 2, executor, *tables);
  ASSERT_TRUE(second.ok()) << second.message;
  const VisiblePoints visible = select_visible_points(points, map_gaze(kRaysW, kRaysH, second.centre_px));
  const glm::vec2 centre(0.5f * float(points.canvas_width_px), 0.5f * float(points.canvas_height_px));
  const uint32_t beside_edge = point_ray_count(kRays, float(kPixelDiscRadiusPx), 1.0f, kRaysContrast);
  ASSERT_LT(beside_edge, uint32_t(kRays));
  std::size_t exact = 0, margin_edge = 0, margin_flat = 0;
  for (std::size_t v = 0; v < visible.size(); ++v) {
    const uint32_t id = visible.point_index[v];
    if (!points.on_pixel_grid(id)) continue;
    const uint32_t rays = scene.rays_of_point[id];
    ASSERT_GT(rays, 0u) << "grid point " << id << " is never thinned";
    const double distance_px = glm::distance(points.position_px[id], centre);
    ASSERT_EQ(points.in_exact_fovea(id), distance_px <= exact_px) << "grid point " << id;
    if (points.in_exact_fovea(id)) {
      ++exact;
      EXPECT_EQ(rays, uint32_t(kRays)) << "grid point " << id << ": the pixel-exact fovea keeps its rays";
      continue;
    }
    const float x = visible.screen_px[v].x;
    if (x < kRaysEdgeX + 16.0f) {  // the tiles beside the edge
      ++margin_edge;
      EXPECT_EQ(rays, beside_edge) << "margin point " << id << " at x = " << x;
    } else if (x >= kRaysEdgeX + 32.0f) {  // flat tiles, their neighbours flat too
      ++margin_flat;
      EXPECT_EQ(rays, 1u) << "margin point " << id << " at x = " << x;
    }
  }
  EXPECT_GT(exact, 2000u);
  EXPECT_GT(margin_edge, 20u);
  EXPECT_GT(margin_flat, 500u);
  std::cout << "[ measured ] grid points: " << exact << " of the exact fovea, " << margin_edge << " + " << margin_flat
            << " of the margin beside the edge and in flat tiles\n";
}

// The contrast doubling every 10 degrees: beside the edge, a Poisson point casts what its disc
// and the edge tile's contrast give at the contrast of its eccentricity's step (counted here
// from the eccentricity, atan(distance / D)); fewer rays than without the steps, none more.
TEST(PointRayCount, BeyondEachEccentricityStepAPointCastsAsItsDoubledContrastGives) {
  constexpr float kDoublingDeg = 10.0f;
  Executor executor(2);
  ViewSettings settings = ray_settings(0.5f);
  settings.content_density.rays_doubling_ecc_deg = kDoublingDeg;
  FoveatedView stepped(ray_tables(), settings), flat(ray_tables(), ray_settings(0.5f));
  RayScene with_steps, without;
  ASSERT_TRUE(render_counting(stepped, with_steps, 1, executor).ok());
  ASSERT_TRUE(render_counting(flat, without, 1, executor).ok());
  const FrameResult second = render_counting(stepped, with_steps, 2, executor);
  ASSERT_TRUE(second.ok()) << second.message;
  const FrameResult second_flat = render_counting(flat, without, 2, executor);
  ASSERT_TRUE(second_flat.ok());
  EXPECT_LT(second.rays, second_flat.rays);

  const PointSet& points = ray_tables()->points;
  // The tiles' luminance as ContentDensity::observe takes it (Rec. 709 weights, exposure 1) from grey.
  const auto luminance = [](float grey) { return 0.2126f * grey + 0.7152f * grey + 0.0722f * grey; };
  const float edge_contrast =
      tile_contrast(luminance(with_steps.left), luminance(with_steps.right), ContentDensityOptions{}.dark_luminance);
  const glm::vec2 centre(0.5f * float(points.canvas_width_px), 0.5f * float(points.canvas_height_px));
  const VisiblePoints visible = select_visible_points(points, map_gaze(kRaysW, kRaysH, second.centre_px));
  std::vector<std::size_t> edge_points_per_step(kRaysContrastSteps + 1, 0);
  for (std::size_t v = 0; v < visible.size(); ++v) {
    const uint32_t id = visible.point_index[v];
    EXPECT_LE(with_steps.rays_of_point[id], without.rays_of_point[id]) << "point " << id;
    const float x = visible.screen_px[v].x;
    if (points.on_pixel_grid(id) || x < kRaysEdgeX - 16.0f || x >= kRaysEdgeX + 16.0f) continue;
    const double ecc_deg = eccentricity_deg(glm::distance(points.position_px[id], centre), points.view_distance_px);
    const double steps = ecc_deg / double(kDoublingDeg);
    if (std::fabs(steps - std::round(steps)) < 1e-3) continue;  // on a step: float rounding decides
    const int step = std::min(int(steps), kRaysContrastSteps);
    ++edge_points_per_step[std::size_t(step)];
    EXPECT_EQ(with_steps.rays_of_point[id],
              point_ray_count(kRays, points.radius_px[id], edge_contrast, 0.5f * float(1 << step)))
        << "point " << id << " at " << ecc_deg << " deg";
  }
  std::size_t beyond_second_step = 0;
  for (std::size_t s = 2; s < edge_points_per_step.size(); ++s) beyond_second_step += edge_points_per_step[s];
  EXPECT_GT(beyond_second_step, 20u) << "edge points where the doubled contrast is above the edge's";
  std::cout << "[ measured ] rays of the second frame with the contrast doubling every " << kDoublingDeg
            << " deg: " << second.rays << ", without: " << second_flat.rays << "\n";
}

TEST(PointRayCount, ADarkTileReadsAsFlat) {
  Executor executor(2);
  RayScene dark;
  dark.left = 0.0f, dark.right = 0.0005f;  // an edge below the dark floor (ContentDensityOptions::dark_luminance)
  FoveatedView view(ray_tables(), ray_settings(kRaysContrast));
  ASSERT_TRUE(render_counting(view, dark, 1, executor).ok());
  const FrameResult second = render_counting(view, dark, 2, executor);
  ASSERT_TRUE(second.ok());
  const PointSet& points = ray_tables()->points;
  std::size_t poisson = 0;
  for (std::size_t id = 0; id < points.size(); ++id) {
    if (dark.rays_of_point[id] == 0 || points.on_pixel_grid(id)) continue;
    ++poisson;
    EXPECT_LE(dark.rays_of_point[id], 1u) << "point " << id << " of a dark edge";
  }
  EXPECT_GT(poisson, 200u);
}

TEST(PointRayCount, OffUnlessAskedFor) {
  EXPECT_FALSE(ViewSettings{}.content_density.varies_rays());
  ContentDensityOptions thin_only;
  thin_only.full_contrast = 0.2f;
  EXPECT_TRUE(thin_only.enabled());
  EXPECT_FALSE(thin_only.varies_rays()) << "thinning alone keeps every point's rays";
}

}  // namespace
}  // namespace foveart::foveation::point_ray_count_test
