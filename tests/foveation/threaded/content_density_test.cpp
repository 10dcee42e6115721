// Content-aware density (foveation/content_density.hpp, point_levels.hpp): the nested
// levels keep their spacing and parents, a flat view traces level 0 alone from its
// second frame and gives the same image, an edge keeps every point of the tiles beside
// it (on a tile border too), the pixel-exact fovea is never thinned, a failed frame makes
// the next trace every point, the render cache takes only the traced points' rays, a box's tiles bound the levels of the points
// in it (the per-point test's shortcut), its cost is reported per stage, and it is
// off unless asked for.
#include <algorithm>
#include <cmath>
#include <iostream>
#include <mutex>
#include <set>
#include <vector>

#include <gtest/gtest.h>

#include "foveation/content_density.hpp"
#include "foveation/display_model.hpp"
#include "foveation/foveated_view.hpp"
#include "foveation/point_levels.hpp"
#include "foveation/visible_points.hpp"
#include "threaded/small_view.hpp"

namespace foveart::foveation::content_density_test {
namespace {

constexpr uint32_t kW = 128;
constexpr uint32_t kH = 96;
constexpr float kEdgeX = 48.0f;  // a tile border (16 px tiles)

// Scale 4: the pixel grid's edge lies inside the view, so frames hold grid and Poisson points.
std::shared_ptr<const ViewTables> tables() {
  static const std::shared_ptr<const ViewTables> t = small_view::tables(kW, kH, 4.0, 3, InterpMethod::msm, 5);
  return t;
}

FrameRequest request(uint64_t frame_index) { return small_view::request(kW, kH, frame_index); }

ViewSettings settings(float full_contrast, TemporalMode temporal = TemporalMode::off) {
  ViewSettings s = temporal_view_settings(temporal, 1, 1);
  s.content_density.full_contrast = full_contrast;
  return s;
}

// The engine: a scene by screen position, recording the points it was asked for.
struct Scene {
  bool edge = false;  // dark left of kEdgeX, white right of it; else flat grey
  bool fail = false;
  std::mutex mutex;
  std::set<uint32_t> points;
};

int32_t trace(void* user, const FoveartRayBatch* batch) {
  auto* scene = static_cast<Scene*>(user);
  if (scene->fail) return FOVEART_RESULT_ERROR_ENGINE_FAILURE;
  std::lock_guard lock(scene->mutex);
  for (uint32_t i = 0; i < batch->ray_count; ++i) {
    const float v = !scene->edge ? 0.4f : (batch->sample_px[i * 2] < kEdgeX ? 0.02f : 1.0f);
    for (int c = 0; c < 3; ++c) batch->out_rgb[i * 3 + c] = v;
    scene->points.insert(batch->point_index[i]);
  }
  return FOVEART_RESULT_SUCCESS;
}

FrameResult render(FoveatedView& view, Scene& scene, uint64_t frame_index, Executor& executor) {
  scene.points.clear();
  return view.render(request(frame_index), &trace, &scene, executor);
}

float max_difference(const ImageRgb& a, const ImageRgb& b) {
  float d = 0.0f;
  for (std::size_t i = 0; i < a.rgb.size(); ++i) d = std::max(d, std::fabs(a.rgb[i] - b.rgb[i]));
  return d;
}

TEST(PointLevels, NestedSubsetsKeepTheirSpacingAndTracedParents) {
  Executor executor(2);
  const PointSet& points = tables()->points;
  const PointLevels levels = build_point_levels(points, executor);
  ASSERT_EQ(levels.size(), points.size());
  std::size_t poisson = 0, poisson_level0 = 0, poisson_level01 = 0, poisson_level012 = 0;
  std::vector<std::size_t> level0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (points.on_pixel_grid(i)) {
      EXPECT_EQ(levels.level[i], 0) << "grid point " << i << ": the pixel-exact fovea is level 0";
      continue;
    }
    ++poisson;
    poisson_level0 += levels.level[i] == 0 ? 1 : 0;
    poisson_level01 += levels.level[i] <= 1 ? 1 : 0;
    poisson_level012 += levels.level[i] <= 2 ? 1 : 0;
    if (levels.level[i] == 0) level0.push_back(i);
  }
  ASSERT_GT(poisson, 1000u);
  // Three times the spacing keeps about a ninth; twice about a quarter; sqrt(2) times about half.
  const double n = double(poisson);
  std::cout << "[ measured ] levels 0, 0-1, 0-2 hold " << double(poisson_level0) / n << ", "
            << double(poisson_level01) / n << ", " << double(poisson_level012) / n << " of the Poisson points\n";
  EXPECT_GT(double(poisson_level0) / n, 0.05);
  EXPECT_LT(double(poisson_level0) / n, 0.20);
  EXPECT_GT(double(poisson_level01) / n, 0.15);
  EXPECT_LT(double(poisson_level01) / n, 0.40);
  EXPECT_GT(double(poisson_level012) / n, 0.35);
  EXPECT_LT(double(poisson_level012) / n, 0.75);
  // A level-0 Poisson point lies at least three times its radius from every level-0 point before it.
  for (std::size_t b = 0; b < level0.size(); ++b)
    for (std::size_t a = 0; a < b; ++a) {
      const std::size_t i = level0[a], j = level0[b];
      ASSERT_GE(glm::distance(points.position_px[i], points.position_px[j]),
                kLevelSpacing[0] * points.radius_px[j] * 0.999f)
          << "level-0 points " << i << " and " << j;
    }
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (levels.level[i] == 0) continue;
    float sum = 0.0f;
    for (uint32_t j = 0; j < PointLevels::kParents; ++j) {
      const uint32_t p = levels.parent[i][j];
      if (p == PointLevels::kNoParent) continue;
      EXPECT_EQ(levels.level[p], 0) << "point " << i << "'s parent " << p;
      sum += levels.parent_weight[i][j];
    }
    ASSERT_NE(levels.parent[i][0], PointLevels::kNoParent) << "point " << i;
    EXPECT_NEAR(sum, 1.0f, 1e-5f) << "point " << i;
  }
  const PointLevels again = build_point_levels(points, executor);
  EXPECT_EQ(again.level, levels.level) << "deterministic for the set";
}

TEST(ContentDensity, ContrastAndLevels) {
  EXPECT_EQ(tile_contrast(0.5f, 0.5f, 0.01f), 0.0f);
  EXPECT_FLOAT_EQ(tile_contrast(0.0f, 1.0f, 0.0f), 1.0f);
  EXPECT_LT(tile_contrast(0.0f, 0.001f, 0.01f), 0.05f) << "dark tiles read as flat";
  EXPECT_EQ(tile_contrast(INFINITY, -INFINITY, 0.01f), 0.0f) << "a tile nobody observed";
  ContentDensityOptions o;
  EXPECT_EQ(level_for_contrast(0.0f, o), PointLevels::kFinest) << "off: every point";
  o.full_contrast = 0.2f;
  EXPECT_EQ(level_for_contrast(0.3f, o), 3);
  EXPECT_EQ(level_for_contrast(0.15f, o), 2);
  EXPECT_EQ(level_for_contrast(0.07f, o), 1);
  EXPECT_EQ(level_for_contrast(0.01f, o), 0);
}

// The run-level shortcut of the per-point test: levels_under() of a screen box is the
// lowest and highest level of the tiles under it, for power-of-two tiles (a shift) and
// others (a division), boxes reaching into the margin included.
TEST(ContentDensity, LevelsUnderABoxAreItsTilesLowestAndHighest) {
  Executor executor(1);
  const PointLevels levels = build_point_levels(tables()->points, executor);
  GazeMapping mapping;
  mapping.screen_width_px = int(kW), mapping.screen_height_px = int(kH);
  for (const int tile_px : {16, 12}) {
    ContentDensityOptions options;
    options.full_contrast = 0.25f;
    options.tile_px = tile_px;
    ContentDensity density(levels, options);
    density.begin_frame(mapping, 1);
    EXPECT_EQ(density.levels_under({0, 0}, {kW, kH}).lowest, PointLevels::kFinest) << "the first frame thins nothing";
    // Grey stripes whose contrast rises to the right in steps, so that tiles span every level.
    for (uint32_t y = 0; y < kH; ++y)
      for (uint32_t x = 0; x < kW; ++x) {
        const float l = 0.5f + float(x % 2) * 0.05f * float(x / 16);
        density.observe(0, {float(x) + 0.5f, float(y) + 0.5f}, Rgba{l, l, l, 1.0f});
      }
    density.end_frame(true);
    density.begin_frame(mapping, 1);
    std::set<uint8_t> seen;
    for (const glm::vec4 box : {glm::vec4(0, 0, kW - 1, kH - 1), glm::vec4(-6, -3, 20, 15), glm::vec4(17, 5, 47.9f, 30),
                                glm::vec4(60, 40, 61, 41), glm::vec4(100, 80, kW + 5, kH + 5)}) {
      uint8_t lowest = PointLevels::kFinest, highest = 0;
      for (float y = box.y; y <= box.w; y += 0.5f)
        for (float x = box.x; x <= box.z; x += 0.5f) {
          const uint8_t level = level_for_contrast(density.contrast({x, y}), options);
          lowest = std::min(lowest, level), highest = std::max(highest, level);
          seen.insert(level);
        }
      const ContentDensity::LevelRange range = density.levels_under({box.x, box.y}, {box.z, box.w});
      EXPECT_EQ(range.lowest, lowest) << "tile " << tile_px << " box " << box.x << "," << box.y;
      EXPECT_EQ(range.highest, highest) << "tile " << tile_px << " box " << box.x << "," << box.y;
    }
    EXPECT_EQ(seen.size(), std::size_t(PointLevels::kLevels)) << "the steps give the tiles every level";
  }
}

TEST(ContentDensity, FlatViewTracesLevelZeroFromItsSecondFrameWithTheSameImage) {
  Executor executor(2);
  Scene scene;
  FoveatedView view(tables(), settings(0.05f));
  const FrameResult first = render(view, scene, 1, executor);
  ASSERT_TRUE(first.ok()) << first.message;
  EXPECT_EQ(first.points_thinned, 0u) << "no contrast measured yet";
  const ImageRgb full = view.image();
  const FrameResult second = render(view, scene, 2, executor);
  ASSERT_TRUE(second.ok()) << second.message;

  const PointLevels& levels = tables()->levels(executor);
  const VisiblePoints visible = select_visible_points(tables()->points, map_gaze(kW, kH, second.centre_px));
  std::size_t level0 = 0;
  for (uint32_t i : visible.point_index) {
    level0 += levels.level[i] == 0 ? 1 : 0;
    if (levels.level[i] == 0) {
      EXPECT_TRUE(scene.points.count(i)) << "level-0 point " << i << " not traced";
    }
    if (tables()->points.on_pixel_grid(i)) {
      EXPECT_TRUE(scene.points.count(i)) << "grid point " << i << " thinned";
    }
  }
  // Level 0, and the few finer points beside the margin whose parents lie beyond it.
  EXPECT_GE(second.points, level0);
  EXPECT_LT(second.points, level0 + level0 / 50);
  EXPECT_EQ(second.points + second.points_thinned, first.points) << "every visible point has a colour";
  EXPECT_LT(double(second.points), 0.8 * double(first.points));
  EXPECT_LT(max_difference(full, view.image()), 1e-6f) << "a flat view's fill is its colour";
  // The record of each point's rays: one for a traced point, none for a filled one (its colour
  // is its parents') nor for a point off the screen.
  const TracedPoints& traced = *view.hand_off().traced;
  std::size_t filled = 0, cast = 0;
  for (uint32_t i = 0; i < tables()->points.size(); ++i) {
    const bool coloured = traced.colors.rgba[i].a == 1.0f;
    const bool was_traced = scene.points.count(i) != 0;
    ASSERT_EQ(traced.rays_cast[i], was_traced ? 1u : 0u) << "point " << i;
    filled += coloured && !was_traced ? 1 : 0;
    cast += traced.rays_cast[i];
  }
  EXPECT_EQ(filled, second.points_thinned);
  EXPECT_EQ(cast, second.rays);
}

TEST(ContentDensity, AnEdgeOnATileBorderKeepsEveryPointOfTheTilesBesideIt) {
  Executor executor(2);
  Scene thin_scene, full_scene;
  thin_scene.edge = full_scene.edge = true;
  FoveatedView thinned(tables(), settings(0.05f)), full(tables(), settings(0.0f));
  for (uint64_t f = 1; f <= 2; ++f) {
    ASSERT_TRUE(render(full, full_scene, f, executor).ok());
    const FrameResult r = render(thinned, thin_scene, f, executor);
    ASSERT_TRUE(r.ok()) << r.message;
    if (f == 2) {
      EXPECT_GT(r.points_thinned, 0u) << "the flat tiles away from the edge thin";
    }
  }
  const VisiblePoints visible = select_visible_points(tables()->points, map_gaze(kW, kH, {kW / 2.0f, kH / 2.0f}));
  std::size_t beside = 0;
  for (std::size_t v = 0; v < visible.size(); ++v) {
    const float x = visible.screen_px[v].x;
    if (x < kEdgeX - 16.0f || x >= kEdgeX + 16.0f) continue;
    ++beside;
    EXPECT_TRUE(thin_scene.points.count(visible.point_index[v]))
        << "point " << visible.point_index[v] << " at x = " << x << " beside the edge was thinned";
  }
  EXPECT_GT(beside, 100u);
  // Away from the edge each side is flat, so the fill is exact: the frames agree.
  EXPECT_LT(max_difference(full.image(), thinned.image()), 1e-5f);
}

TEST(ContentDensity, ItsCostIsReportedPerStageAsAPartOfSelectAndTrace) {
  Executor executor(2);
  Scene scene, off_scene;
  scene.edge = off_scene.edge = true;
  FoveatedView view(tables(), settings(0.05f)), off(tables(), settings(0.0f));
  for (uint64_t f = 1; f <= 2; ++f) {
    const FrameResult r = render(view, scene, f, executor), o = render(off, off_scene, f, executor);
    ASSERT_TRUE(r.ok() && o.ok()) << r.message << o.message;
    EXPECT_EQ(o.density_ms, 0.0) << "off: no density stage";
    EXPECT_EQ(o.density.total_ms(), 0.0);
    EXPECT_DOUBLE_EQ(r.density_ms, r.density.total_ms()) << "frame " << f;
    // The stages run within the frame's select and trace (the per-point ones: CPU time over the threads).
    EXPECT_LE(r.density_ms, r.select_ms + r.trace_ms) << "frame " << f;
    if (f == 1) continue;
    ASSERT_GT(r.points_thinned, 0u);
    EXPECT_GT(r.density.levels_ms, 0.0) << "the tiles' levels from the first frame's ranges";
    EXPECT_GT(r.density.test_ms, 0.0) << "every visible point was tested";
    EXPECT_GT(r.density.observe_ms, 0.0) << "every traced colour was observed";
    EXPECT_GT(r.density.fill_ms, 0.0) << "the thinned points were filled";
  }
}

TEST(ContentDensity, AFailedFrameTracesEveryPointInTheNext) {
  Executor executor(2);
  Scene scene;
  FoveatedView view(tables(), settings(0.05f));
  ASSERT_TRUE(render(view, scene, 1, executor).ok());
  scene.fail = true;
  EXPECT_FALSE(render(view, scene, 2, executor).ok());
  scene.fail = false;
  const FrameResult after = render(view, scene, 3, executor);
  ASSERT_TRUE(after.ok());
  EXPECT_EQ(after.points_thinned, 0u) << "the frame after a failure measures again";
}

// With the render cache ("rays") content density thins too: from the second frame of a
// flat view the cache takes only the traced points' rays (the engine gives no depth, so
// none is covered and the cache holds every ray traced since the first frame), and the
// frame stays the flat grey: the pixels no ray reaches show the gather of the filled points.
TEST(ContentDensity, TheRenderCacheKeepsOnlyTheTracedPointsRays) {
  Executor executor(2);
  Scene scene;
  FoveatedView view(tables(), settings(0.05f, TemporalMode::rays));
  const FrameResult first = render(view, scene, 1, executor);
  ASSERT_TRUE(first.ok());
  EXPECT_EQ(first.points_thinned, 0u);
  EXPECT_EQ(view.cached_rays(), first.rays);
  const ImageRgb first_image = view.image();
  uint64_t traced = first.rays;
  for (uint64_t f = 2; f <= 3; ++f) {
    const FrameResult r = render(view, scene, f, executor);
    ASSERT_TRUE(r.ok());
    EXPECT_GT(r.points_thinned, first.points / 4) << "frame " << f;
    EXPECT_LT(r.rays, first.rays) << "frame " << f;
    EXPECT_EQ(scene.points.size(), r.points) << "frame " << f << ": the engine saw the traced points only";
    traced += r.rays;
    EXPECT_EQ(view.cached_rays(), traced) << "frame " << f;
    EXPECT_LT(max_difference(view.image(), first_image), 1e-5f) << "frame " << f;
  }
}

TEST(ContentDensity, OffUnlessAskedFor) {
  Executor executor(2);
  Scene scene;
  EXPECT_FALSE(ViewSettings{}.content_density.enabled());
  FoveatedView view(tables(), ViewSettings{});
  for (uint64_t f = 1; f <= 3; ++f) {
    const FrameResult r = render(view, scene, f, executor);
    ASSERT_TRUE(r.ok());
    EXPECT_EQ(r.points_thinned, 0u);
  }
}

}  // namespace
}  // namespace foveart::foveation::content_density_test
