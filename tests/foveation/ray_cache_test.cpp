// The render cache (foveation/ray_cache.hpp): where its kept rays land in a
// new view, how it filters them, and when it forgets them.
#include <cmath>
#include <vector>

#include <glm/gtc/quaternion.hpp>
#include <gtest/gtest.h>

#include "foveation/eye_rays.hpp"
#include "foveation/ray_cache.hpp"

namespace foveart::foveation {
namespace {

constexpr std::uint32_t kW = 32, kH = 24;

FoveartEyeView view_at(glm::vec3 position_m, float yaw_deg) {
  EyePose pose;
  pose.position_m = position_m;
  pose.orientation = glm::angleAxis(glm::radians(-yaw_deg), glm::vec3(0, 1, 0));
  return make_eye_view(0, kW, kH, pose, -0.5f, 0.5f, 0.45f, -0.45f);
}

// One ray through every pixel centre of `view`, colour (x, y, frame), hitting at depth_m.
void add_pixel_centres(RayCache& cache, int frame, float depth_m) {
  const std::size_t first = cache.add_rays(std::size_t(kW) * kH);
  for (std::uint32_t y = 0; y < kH; ++y)
    for (std::uint32_t x = 0; x < kW; ++x)
      cache.set_ray(first + y * kW + x, glm::vec2(float(x) + 0.5f, float(y) + 0.5f),
                    glm::vec3(float(x), float(y), float(frame)), depth_m);
}

TEST(PixelFilterWeight, EachFilterSplitsARayIntoWeightsThatSumToOne) {
  for (const PixelFilter filter : {PixelFilter::box, PixelFilter::bspline2}) {
    for (float u = -0.5f; u < 0.5f; u += 0.0625f) {  // a ray u from a pixel centre: its weights over every pixel
      float sum = 0.0f;
      for (int k = -3; k <= 3; ++k) {
        const float w = pixel_filter_weight(filter, u - float(k));
        EXPECT_GE(w, 0.0f);
        sum += w;
      }
      EXPECT_NEAR(sum, 1.0f, 1e-6f) << pixel_filter_name(filter) << " u " << u;
    }
  }
  // Box: the pixel floor() assigns a ray to; bspline2: 3 px wide, peak 3/4.
  EXPECT_EQ(pixel_filter_weight(PixelFilter::box, -0.5f), 1.0f);
  EXPECT_EQ(pixel_filter_weight(PixelFilter::box, 0.5f), 0.0f);
  EXPECT_FLOAT_EQ(pixel_filter_weight(PixelFilter::bspline2, 0.0f), 0.75f);
  EXPECT_FLOAT_EQ(pixel_filter_weight(PixelFilter::bspline2, 1.0f), 0.125f);
  EXPECT_EQ(pixel_filter_weight(PixelFilter::bspline2, 1.5f), 0.0f);
  // The splat's three weights of a ray are the same spline.
  for (float t = -0.5f; t < 0.5f; t += 0.0625f) {
    float w[3];
    bspline2_weights(t, w);
    for (int j = 0; j < 3; ++j)
      EXPECT_NEAR(w[j], pixel_filter_weight(PixelFilter::bspline2, t + 1.0f - float(j)), 1e-6f) << "t " << t;
  }
}

// filter_at (and cache_filter.comp) reads the cells filter_window_cells names: every ray
// inside a window lies in them, and the first and the last each overlap the window, so no
// cell is read for nothing. At footprint 1 that is 2 cells per axis for bspline2
// and 1 for box at every pixel (a closed window's floor() read a third, or a second, at
// every other pixel).
TEST(RayCache, AFilterWindowReadsTheCellsThatHoldItsRaysAndNoMore) {
  constexpr float kStepPx = 1.0f / 16.0f;
  for (const float half_width : {0.5f, 1.5f}) {
    for (const float footprint_px : {1.0f, 1.37f, 2.0f, 3.5f}) {
      const float r_px = half_width * footprint_px;
      for (float centre_px = 0.5f; centre_px < 12.0f; centre_px += 0.25f) {
        SCOPED_TRACE("half width " + std::to_string(half_width) + ", footprint " + std::to_string(footprint_px) +
                     ", centre " + std::to_string(centre_px));
        const CellRange cells = filter_window_cells(glm::vec2(centre_px, 3.0f * centre_px), r_px);
        for (float q_px = centre_px - r_px - 2.0f; q_px < centre_px + r_px + 2.0f; q_px += kStepPx) {
          const float t = (q_px - centre_px) / footprint_px;
          if (t < -half_width || t >= half_width) continue;  // filter_at's test of a ray
          const int cell = ray_cache_cell(glm::vec2(q_px)).x;
          ASSERT_GE(cell, cells.first.x) << "a ray at " << q_px << " px in the window lies before the cells read";
          ASSERT_LE(cell, cells.last.x) << "a ray at " << q_px << " px in the window lies after the cells read";
        }
        // Cell c covers [(c - 1) C, c C): the first ends after the window starts, the last starts before it ends.
        const double cell_px = FOVEART_RAY_CACHE_CELL_PX;
        const double window_lo_px = double(centre_px) - double(r_px), window_hi_px = double(centre_px) + double(r_px);
        EXPECT_GT(cells.first.x * cell_px, window_lo_px) << "the first cell read ends before the window";
        EXPECT_LT((cells.last.x - 1) * cell_px, window_hi_px)
            << "the last cell read starts at or after the window's end";
        const CellRange y = filter_window_cells(glm::vec2(3.0f * centre_px, centre_px), r_px);
        EXPECT_EQ(y.first.y, cells.first.x);  // the axes are alike
        EXPECT_EQ(y.last.y, cells.last.x);
        if (footprint_px == 1.0f && centre_px - std::floor(centre_px) == 0.5f) {
          EXPECT_EQ(cells.last.x - cells.first.x + 1, half_width == 0.5f ? 1 : 2) << "a pixel's cells per axis";
        }
      }
    }
  }
}

// A kept hit lands where its surface point now projects (parallax); a kept
// ray without depth is a direction, which a sideways step does not move.
TEST(RayCache, KeptRaysLandWhereTheirAnchorProjectsInTheNewView) {
  Executor executor(2);
  const FoveartEyeView before = view_at({0, 1.6f, 0}, 0.0f), after = view_at({0.3f, 1.6f, 0}, 5.0f);
  const glm::vec2 sample_px(9.25f, 13.5f);
  for (const float depth_m : {2.0f, NAN}) {
    RayCache cache;
    cache.begin_frame(before, executor);
    cache.set_ray(cache.add_rays(1), sample_px, glm::vec3(1.0f), depth_m);
    ImageRgb image;
    cache.resolve(executor, &image);
    ASSERT_EQ(cache.size(), 1u);

    cache.begin_frame(after, executor);
    ASSERT_EQ(cache.kept(), 1u);
    const EyePose p0 = eye_pose(before), p1 = eye_pose(after);
    const glm::vec3 d0 = eye_ray_direction(eye_frustum(before), p0, sample_px);
    const glm::vec3 d1 = std::isnan(depth_m) ? d0 : glm::normalize(p0.position_m + d0 * depth_m - p1.position_m);
    glm::vec2 expected_px(0.0f);
    ASSERT_TRUE(project_direction(eye_frustum(after), p1, d1, &expected_px));
    EXPECT_TRUE(cache.kept_on_screen(0));
    EXPECT_NEAR(cache.kept_sample_px(0).x, expected_px.x, 1e-3f) << "depth " << depth_m;
    EXPECT_NEAR(cache.kept_sample_px(0).y, expected_px.y, 1e-3f) << "depth " << depth_m;
    // The step moves a hit 2 m away by pixels, and the step's yaw moves both.
    EXPECT_GT(std::abs(cache.kept_sample_px(0).x - sample_px.x), 1.0f);
  }
}

// Box filter: a pixel is the mean of the rays inside it, its weight their count.
TEST(RayCache, BoxFilterGivesEachPixelTheMeanOfItsRays) {
  Executor executor(2);
  RayCache cache;
  cache.begin_frame(view_at({0, 1.6f, 0}, 0.0f), executor);
  const std::size_t first = cache.add_rays(3);
  cache.set_ray(first + 0, {4.1f, 5.9f}, {1.0f, 0.0f, 0.0f}, 3.0f);
  cache.set_ray(first + 1, {4.9f, 5.1f}, {0.0f, 1.0f, 0.0f}, 3.0f);
  cache.set_ray(first + 2, {5.0f, 5.5f}, {0.0f, 0.0f, 1.0f}, 3.0f);  // the next pixel: [-0.5, 0.5) of 5.5
  ImageRgb image;
  std::vector<float> weight;
  cache.resolve(executor, &image, &weight);
  ASSERT_EQ(image.width_px, int(kW));
  EXPECT_EQ(weight[5 * kW + 4], 2.0f);
  EXPECT_EQ(weight[5 * kW + 5], 1.0f);
  EXPECT_EQ(weight[5 * kW + 3], 0.0f);
  EXPECT_FLOAT_EQ(image.at(4, 5)[0], 0.5f);
  EXPECT_FLOAT_EQ(image.at(4, 5)[1], 0.5f);
  EXPECT_FLOAT_EQ(image.at(5, 5)[2], 1.0f);
  EXPECT_EQ(image.at(3, 5)[0], 0.0f);
}

// bspline2: one ray at a pixel centre spreads over the 3x3 pixels around it
// with the spline's weights, 3/4 and 1/8 per axis.
TEST(RayCache, Bspline2SpreadsARayOverThe3x3PixelsAroundIt) {
  Executor executor(2);
  RayCache cache(RayCacheOptions{PixelFilter::bspline2});
  cache.begin_frame(view_at({0, 1.6f, 0}, 0.0f), executor);
  cache.set_ray(cache.add_rays(1), {10.5f, 8.5f}, {0.25f, 0.5f, 1.0f}, 3.0f);
  ImageRgb image;
  std::vector<float> weight;
  cache.resolve(executor, &image, &weight);
  for (int dy = -2; dy <= 2; ++dy)
    for (int dx = -2; dx <= 2; ++dx) {
      const float wx = std::abs(dx) == 0 ? 0.75f : std::abs(dx) == 1 ? 0.125f : 0.0f;
      const float wy = std::abs(dy) == 0 ? 0.75f : std::abs(dy) == 1 ? 0.125f : 0.0f;
      const std::size_t p = std::size_t(8 + dy) * kW + std::size_t(10 + dx);
      EXPECT_FLOAT_EQ(weight[p], wx * wy) << dx << "," << dy;
      if (wx * wy > 0.0f) {
        EXPECT_FLOAT_EQ(image.at(10 + dx, 8 + dy)[1], 0.5f) << dx << "," << dy;
      }
    }
}

// On a still view a ray is filtered into max_age_frames frames, the one it
// was traced in included, then forgotten: the weight settles at that many rays per pixel.
TEST(RayCache, RaysOlderThanTheAgeLimitAreForgotten) {
  Executor executor(2);
  RayCacheOptions options;
  options.max_age_frames = 3;
  RayCache cache(options);
  const FoveartEyeView view = view_at({0, 1.6f, 0}, 0.0f);
  ImageRgb image;
  std::vector<float> weight;
  for (int frame = 0; frame < 6; ++frame) {
    cache.begin_frame(view, executor);
    add_pixel_centres(cache, frame, 4.0f);
    cache.resolve(executor, &image, &weight);
    const float rays_per_pixel = float(std::min(frame + 1, 3));
    EXPECT_EQ(weight[7 * kW + 11], rays_per_pixel) << "frame " << frame;
    // The frames filtered: the last three (their colour's blue is the frame index).
    const float mean_frame = frame < 3 ? float(frame) / 2.0f : float(frame - 1);
    EXPECT_FLOAT_EQ(image.at(11, 7)[2], mean_frame) << "frame " << frame;
    EXPECT_EQ(cache.size(), std::size_t(kW) * kH * std::size_t(rays_per_pixel == 3.0f ? 2 : frame + 1));
  }
}

// A frame that fails keeps the cache as it was before it.
TEST(RayCache, AnAbandonedFrameKeepsTheKeptRaysAndDropsItsNewOnes) {
  Executor executor(2);
  RayCache cache;
  const FoveartEyeView view = view_at({0, 1.6f, 0}, 0.0f);
  ImageRgb image;
  cache.begin_frame(view, executor);
  add_pixel_centres(cache, 0, 4.0f);
  cache.resolve(executor, &image);
  cache.begin_frame(view, executor);
  add_pixel_centres(cache, 1, 4.0f);
  cache.abandon_frame();
  EXPECT_EQ(cache.size(), std::size_t(kW) * kH);
  cache.begin_frame(view, executor);
  cache.resolve(executor, &image);
  EXPECT_EQ(image.at(3, 2)[2], 0.0f);  // frame 0's colour alone
  EXPECT_EQ(image.at(3, 2)[0], 3.0f);
}

// Off the image beyond the filter's reach a kept ray is forgotten, and a new one never kept.
TEST(RayCache, RaysBeyondTheFiltersReachAreForgotten) {
  Executor executor(2);
  for (const PixelFilter filter : {PixelFilter::box, PixelFilter::bspline2}) {
    RayCache cache(RayCacheOptions{filter});
    ImageRgb image;
    cache.begin_frame(view_at({0, 1.6f, 0}, 0.0f), executor);
    add_pixel_centres(cache, 0, 4.0f);
    cache.resolve(executor, &image);
    cache.begin_frame(view_at({0, 1.6f, 0}, 20.0f), executor);  // the view turns 20 deg of its 57: a third leaves
    std::size_t on_screen = 0;
    for (std::size_t i = 0; i < cache.kept(); ++i) on_screen += cache.kept_on_screen(i) ? 1 : 0;
    cache.resolve(executor, &image);
    EXPECT_EQ(cache.size(), on_screen) << pixel_filter_name(filter);
    EXPECT_LT(on_screen, std::size_t(kW) * kH) << pixel_filter_name(filter);

    // A new ray beyond reach (2 px off the image's left edge) is neither filtered nor kept.
    cache.clear();
    cache.begin_frame(view_at({0, 1.6f, 0}, 0.0f), executor);
    const std::size_t first = cache.add_rays(2);
    cache.set_ray(first, {-2.0f, 5.5f}, glm::vec3(1.0f), 4.0f);
    cache.set_ray(first + 1, {0.0f, 5.5f}, glm::vec3(0.5f), 4.0f);  // on the edge: inside
    std::vector<float> weight;
    cache.resolve(executor, &image, &weight);
    EXPECT_EQ(cache.size(), 1u) << pixel_filter_name(filter);
    EXPECT_FLOAT_EQ(image.at(0, 5)[0], 0.5f) << pixel_filter_name(filter);
  }
}

// Rays spread over the image and a little beyond (a fixed sequence), colour by index.
void add_scattered_rays(RayCache& cache, int n, float depth_m) {
  const std::size_t first = cache.add_rays(std::size_t(n));
  std::uint32_t state = 12345;
  auto next = [&state] {
    state = state * 1664525u + 1013904223u;
    return float(state >> 8) / float(1u << 24);
  };
  for (int i = 0; i < n; ++i) {
    const glm::vec2 q(next() * float(kW + 2) - 1.0f, next() * float(kH + 2) - 1.0f);
    cache.set_ray(first + std::size_t(i), q, glm::vec3(next(), next(), float(i % 7)), depth_m);
  }
}

// A filter at disc_footprint_px spreads a ray with the variance of a uniform
// disc of that radius, r^2 / 4 per axis.
TEST(RayCache, TheDiscFootprintHasTheDiscsVariance) {
  for (const PixelFilter filter : {PixelFilter::box, PixelFilter::bspline2}) {
    for (const float radius_px : {0.5f, 2.0f, 7.5f}) {
      const float footprint = disc_footprint_px(filter, radius_px);
      double sum_w = 0.0, sum_wx2 = 0.0;
      const double step = double(footprint) / 4096.0;
      for (double x = -2.0 * double(footprint); x < 2.0 * double(footprint); x += step) {
        const double w = pixel_filter_weight(filter, float(x / double(footprint)));
        sum_w += w;
        sum_wx2 += w * x * x;
      }
      EXPECT_NEAR(sum_wx2 / sum_w, double(radius_px) * double(radius_px) / 4.0, 1e-3 * double(radius_px * radius_px))
          << pixel_filter_name(filter) << " r " << radius_px;
    }
  }
}

// filter_at with a footprint of 1 at a pixel centre is that pixel's filter:
// the same weights and colour as resolve, kept rays and new ones alike.
TEST(RayCache, FilterAtAPixelCentreWithAFootprintOfOneIsThatPixel) {
  Executor executor(2);
  for (const PixelFilter filter : {PixelFilter::box, PixelFilter::bspline2}) {
    RayCache cache(RayCacheOptions{filter});
    cache.begin_frame(view_at({0, 1.6f, 0}, 0.0f), executor);
    add_scattered_rays(cache, 3000, 4.0f);
    ImageRgb image;
    cache.resolve(executor, &image);
    cache.begin_frame(view_at({0.05f, 1.6f, 0}, 2.0f), executor);
    add_scattered_rays(cache, 3000, 3.0f);
    std::vector<glm::vec2> centres;
    std::vector<float> footprint;
    for (std::uint32_t y = 0; y < kH; ++y)
      for (std::uint32_t x = 0; x < kW; ++x) {
        centres.emplace_back(float(x) + 0.5f, float(y) + 0.5f);
        footprint.push_back(1.0f);
      }
    std::vector<glm::vec3> rgb;
    std::vector<float> point_weight, weight;
    cache.filter_at(centres, footprint, executor, &rgb, &point_weight);
    cache.resolve(executor, &image, &weight);
    for (std::uint32_t y = 0; y < kH; ++y)
      for (std::uint32_t x = 0; x < kW; ++x) {
        const std::size_t p = y * kW + x;
        ASSERT_GT(weight[p], 0.0f);
        EXPECT_NEAR(point_weight[p], weight[p], 1e-4f * weight[p]) << pixel_filter_name(filter) << " " << x << "," << y;
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(rgb[p][c], image.at(int(x), int(y))[c], 1e-4f) << x << "," << y;
      }
  }
}

// A larger footprint scales the filter: a ray d from the centre weighs as one
// d / footprint from a pixel's centre. A centre no ray reaches keeps its colour.
TEST(RayCache, FilterAtScalesTheFilterToTheFootprint) {
  Executor executor(2);
  RayCache cache(RayCacheOptions{PixelFilter::bspline2});
  cache.begin_frame(view_at({0, 1.6f, 0}, 0.0f), executor);
  const glm::vec2 centre(16.0f, 12.0f);
  const glm::vec2 offsets[] = {{0.0f, 0.0f}, {4.0f, 0.0f}, {6.0f, 0.0f}, {2.0f, -4.0f}};
  const float colours[] = {1.0f, 2.0f, 100.0f, 4.0f};
  const std::size_t first = cache.add_rays(4);
  for (std::size_t i = 0; i < 4; ++i) cache.set_ray(first + i, centre + offsets[i], glm::vec3(colours[i]), 3.0f);
  std::vector<glm::vec3> rgb{glm::vec3(0.0f), glm::vec3(-1.0f)};
  std::vector<float> weight;
  cache.filter_at({centre, {2.0f, 2.0f}}, {4.0f, 1.0f}, executor, &rgb, &weight);
  // Offsets in footprints: (0, 0), (1, 0), (1.5, 0) beyond the spline's reach, (0.5, -1).
  const float w[] = {0.75f * 0.75f, 0.125f * 0.75f, 0.0f, 0.5f * 0.125f};
  const float w_sum = w[0] + w[1] + w[2] + w[3];
  EXPECT_FLOAT_EQ(weight[0], w_sum);
  EXPECT_FLOAT_EQ(rgb[0].x, (w[0] * 1.0f + w[1] * 2.0f + w[3] * 4.0f) / w_sum);
  EXPECT_EQ(weight[1], 0.0f);
  EXPECT_EQ(rgb[1].x, -1.0f) << "untouched";
}

// A kept ray a caller forgets (its own depth test) is filtered nowhere and not kept.
TEST(RayCache, AForgottenKeptRayIsNotFilteredAndNotKept) {
  Executor executor(2);
  RayCache cache;
  const FoveartEyeView view = view_at({0, 1.6f, 0}, 0.0f);
  cache.begin_frame(view, executor);
  std::size_t first = cache.add_rays(2);
  cache.set_ray(first, {5.5f, 5.5f}, glm::vec3(1.0f), 3.0f);
  cache.set_ray(first + 1, {5.25f, 5.25f}, glm::vec3(3.0f), 3.0f);
  ImageRgb image;
  cache.resolve(executor, &image);
  ASSERT_EQ(cache.size(), 2u);
  cache.begin_frame(view, executor);
  EXPECT_FLOAT_EQ(cache.distance_m(0), 3.0f);
  cache.forget(1);
  std::vector<glm::vec3> rgb;
  std::vector<float> weight;
  cache.filter_at({{5.5f, 5.5f}}, {1.0f}, executor, &rgb, &weight);
  EXPECT_EQ(weight[0], 1.0f);
  EXPECT_EQ(rgb[0].x, 1.0f);
  cache.resolve(executor, &image);
  EXPECT_EQ(image.at(5, 5)[0], 1.0f);
  EXPECT_EQ(cache.size(), 1u);
}

}  // namespace
}  // namespace foveart::foveation
