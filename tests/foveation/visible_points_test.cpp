// Gaze mapping, visible-point selection and per-point ray samples (thesis 4.2).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <functional>
#include <numeric>
#include <unistd.h>
#include <glm/geometric.hpp>

#include <cmath>
#include <limits>

#include "foveation/callback_trace.hpp"
#include "foveation/content_density.hpp"
#include "foveation/eye_rays.hpp"
#include "foveation/gaze_mapping.hpp"
#include "foveation/point_levels.hpp"
#include "foveation/point_set.hpp"
#include "foveation/ray_samples.hpp"
#include "foveation/visible_points.hpp"

namespace fv = foveart::foveation;

namespace {
const fv::PointSet& small_set() {
  static const fv::PointSet ps = [] {
    auto d = fv::DisplayModel::from_thesis(200, 160, 0.85);
    d.scale = 3.0;
    d.fovea_pattern = fv::FoveaPattern::kThesisPoisson;  // discs everywhere, the thesis's 10 px margin
    return fv::generate_point_set(d, 4);
  }();
  return ps;
}
}  // namespace

TEST(GazeMapping, CentredGazePutsTheCentreOfInterestOnIt) {
  const auto m = fv::map_gaze(200, 160, {100.0f, 80.0f});
  EXPECT_FALSE(m.clamped);
  EXPECT_EQ(m.canvas_from_screen_x_px, 100);
  EXPECT_EQ(m.canvas_from_screen_y_px, 80);
  // Canvas centre (W, H) lands on the gaze.
  const glm::vec2 s = m.screen_from_canvas({200.0f, 160.0f});
  EXPECT_EQ(s, glm::vec2(100.0f, 80.0f));
}

TEST(GazeMapping, OffScreenIsClampedAndReportedNonFiniteIsAnError) {
  const auto m = fv::map_gaze(200, 160, {-30.0f, 500.0f});
  EXPECT_TRUE(m.clamped);
  EXPECT_EQ(m.gaze_px, glm::vec2(0.0f, 160.0f));
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  EXPECT_THROW(fv::map_gaze(200, 160, {nan, 3.0f}), std::invalid_argument);
  EXPECT_THROW(fv::map_gaze(200, 160, {3.0f, inf}), std::invalid_argument);
  EXPECT_THROW(fv::map_gaze(200, 160, {-inf, 0.0f}), std::invalid_argument);
  EXPECT_THROW(fv::map_gaze(0, 160, {0.0f, 0.0f}), std::invalid_argument);
}

TEST(VisiblePoints, ScreenPlusMarginInStableOrder) {
  const auto& ps = small_set();
  for (const glm::vec2 g : {glm::vec2(100, 80), glm::vec2(0, 0), glm::vec2(200, 160), glm::vec2(37.3f, 151.9f)}) {
    const auto m = fv::map_gaze(200, 160, g);
    const auto vis = fv::select_visible_points(ps, m);
    std::size_t expected = 0;
    for (std::size_t i = 0; i < ps.size(); ++i) {
      const glm::vec2 s = m.screen_from_canvas(ps.position_px[i]);
      if (s.x >= -10.0f && s.x < 210.0f && s.y >= -10.0f && s.y < 170.0f) ++expected;
    }
    EXPECT_EQ(vis.size(), expected);
    for (std::size_t v = 0; v < vis.size(); ++v) {
      if (v > 0) {
        ASSERT_LT(vis.point_index[v - 1], vis.point_index[v]);
      }
      EXPECT_EQ(vis.screen_px[v], m.screen_from_canvas(ps.position_px[vis.point_index[v]]));
    }
    // Same gaze, same selection.
    EXPECT_EQ(fv::select_visible_points(ps, m).point_index, vis.point_index);
  }
  // Centred gaze sees the dense middle of the canvas: more points than at a corner.
  EXPECT_GT(fv::select_visible_points(ps, fv::map_gaze(200, 160, {100, 80})).size(),
            fv::select_visible_points(ps, fv::map_gaze(200, 160, {0, 0})).size());
}

namespace {
int32_t grey_engine(void*, const FoveartRayBatch* batch) {
  for (uint32_t i = 0; i < batch->ray_count * 3; ++i) batch->out_rgb[i] = 0.5f;
  for (uint32_t i = 0; i < batch->ray_count; ++i) batch->out_depth_m[i] = 2.0f;
  return FOVEART_RESULT_SUCCESS;
}
// Fails the batches that begin at an odd point of the set.
int32_t half_failing_engine(void* user, const FoveartRayBatch* batch) {
  return batch->point_index[0] % 2 == 1 ? FOVEART_RESULT_ERROR_ENGINE_FAILURE : grey_engine(user, batch);
}
}  // namespace

// The trace pass (stages 1-3) traces exactly the selection, whatever runs of the
// set it skips as wholly off the screen: a set of many runs, gazes from the
// centre to the corners.
TEST(VisiblePoints, TheTracePassTracesExactlyTheVisiblePoints) {
  const fv::PointSet ps = fv::generate_point_set(fv::DisplayModel::from_fov(480, 540, 95.0), 3);
  ASSERT_GT(ps.size(), 4u * 8192u);  // several runs of the trace pass
  fv::Executor executor(2);
  fv::CallbackTrace trace(ps, 1, fv::PixelFilter::box, false, false);
  fv::HostFrame host;  // the trace writes nothing there: its points stay in traced()
  for (const glm::vec2 g : {glm::vec2(240, 270), glm::vec2(0, 0), glm::vec2(480, 540), glm::vec2(450, 20)}) {
    fv::FrameContext frame;
    frame.view = fv::make_eye_view(0, 480, 540, fv::EyePose{}, -0.8f, 0.8f, 0.85f, -0.85f);
    frame.mapping = fv::map_gaze(480, 540, g);
    frame.trace_rays = &grey_engine;
    const fv::TraceStats stats = trace.trace(frame, host, executor);
    std::vector<std::uint32_t> traced;
    for (const auto& run : trace.traced().runs) traced.insert(traced.end(), run.begin(), run.end());
    const fv::VisiblePoints visible = fv::select_visible_points(ps, frame.mapping);
    EXPECT_EQ(traced, visible.point_index) << g.x << "," << g.y;
    EXPECT_EQ(stats.points, visible.size());
    // Exactly the points traced this frame hold a colour: last frame's others are forgotten.
    std::size_t coloured = 0;
    for (std::size_t i = 0; i < ps.size(); ++i) {
      const bool has_colour = trace.traced().colors.rgba[i].a == 1.0f;
      coloured += has_colour;
      EXPECT_EQ(std::isnan(trace.traced().depth_m[i]), !has_colour) << i;
    }
    EXPECT_EQ(coloured, visible.size()) << g.x << "," << g.y;
    EXPECT_LT(visible.size(), ps.size());
  }
  // A frame whose engine fails some batches: their points hold no colour,
  // whether or not they were traced the frame before; the others hold theirs.
  fv::FrameContext frame;
  frame.view = fv::make_eye_view(0, 480, 540, fv::EyePose{}, -0.8f, 0.8f, 0.85f, -0.85f);
  frame.mapping = fv::map_gaze(480, 540, {300, 300});
  frame.trace_rays = &half_failing_engine;
  const fv::TraceStats stats = trace.trace(frame, host, executor);
  EXPECT_GT(stats.failed_batches, 0u);
  std::vector<std::uint32_t> traced;
  for (const auto& run : trace.traced().runs) traced.insert(traced.end(), run.begin(), run.end());
  ASSERT_FALSE(traced.empty());
  std::size_t coloured = 0;
  for (std::size_t i = 0; i < ps.size(); ++i) {
    const bool has_colour = trace.traced().colors.rgba[i].a == 1.0f;
    coloured += has_colour;
    EXPECT_EQ(has_colour, std::binary_search(traced.begin(), traced.end(), std::uint32_t(i))) << i;
  }
  EXPECT_EQ(coloured, traced.size());
  EXPECT_LT(traced.size(), fv::select_visible_points(ps, frame.mapping).size());
}

// With content density the run lists hold the points traced, then those filled from their
// parents; exactly those hold a colour, each once, while the gaze moves and filled points of
// the last frame fall off the screen or are traced again.
TEST(VisiblePoints, WithContentDensityExactlyTheTracedAndFilledPointsHoldAColour) {
  const fv::PointSet ps = fv::generate_point_set(fv::DisplayModel::from_fov(480, 540, 95.0), 3);
  fv::Executor executor(2);
  fv::CallbackTrace trace(ps, 1, fv::PixelFilter::box, false, false);
  const fv::PointLevels levels = fv::build_point_levels(ps, executor);
  fv::ContentDensityOptions options;
  options.full_contrast = 0.5f;  // the grey engine's view is flat: its tiles trace level 0
  trace.set_content_density([&](fv::Executor&) -> const fv::PointLevels& { return levels; }, options);
  fv::HostFrame host;
  std::uint64_t thinned = 0;
  for (const glm::vec2 g : {glm::vec2(240, 270), glm::vec2(240, 270), glm::vec2(0, 0), glm::vec2(480, 540),
                            glm::vec2(450, 20), glm::vec2(240, 270)}) {
    fv::FrameContext frame;
    frame.view = fv::make_eye_view(0, 480, 540, fv::EyePose{}, -0.8f, 0.8f, 0.85f, -0.85f);
    frame.mapping = fv::map_gaze(480, 540, g);
    frame.trace_rays = &grey_engine;
    const fv::TraceStats stats = trace.trace(frame, host, executor);
    ASSERT_TRUE(stats.ok()) << stats.error;
    thinned += stats.points_thinned;
    std::vector<std::uint32_t> listed;
    for (const auto& run : trace.traced().runs) listed.insert(listed.end(), run.begin(), run.end());
    EXPECT_EQ(listed.size(), std::size_t(stats.points) + stats.points_thinned) << g.x << "," << g.y;
    std::sort(listed.begin(), listed.end());
    EXPECT_EQ(std::adjacent_find(listed.begin(), listed.end()), listed.end()) << "a point listed twice";
    std::size_t coloured = 0;
    for (std::size_t i = 0; i < ps.size(); ++i) {
      const bool has_colour = trace.traced().colors.rgba[i].a == 1.0f;
      coloured += has_colour;
      if (has_colour) {
        EXPECT_TRUE(std::binary_search(listed.begin(), listed.end(), std::uint32_t(i))) << i;
      }
    }
    EXPECT_EQ(coloured, listed.size()) << g.x << "," << g.y;
  }
  EXPECT_GT(thinned, 0u) << "a flat view thins from its second frame";
}

TEST(RaySamples, UniformInsideEachDiscAndIdenticalEveryFrame) {
  const auto& ps = small_set();
  const auto vis = fv::select_visible_points(ps, fv::map_gaze(200, 160, {100, 80}));
  const int spp = 8;
  const auto a = fv::generate_ray_samples(ps, vis, spp, 1234, 200);
  ASSERT_EQ(a.size(), vis.size() * spp);
  double sum_r2 = 0.0;
  for (std::size_t v = 0; v < vis.size(); ++v) {
    for (int s = 0; s < spp; ++s) {
      const std::size_t o = v * spp + std::size_t(s);
      ASSERT_EQ(a.point_index[o], vis.point_index[v]);
      const float r = ps.radius_px[vis.point_index[v]];
      const float dist = glm::length(a.sample_px[o] - vis.screen_px[v]);
      ASSERT_LE(dist, r * 1.0001f);
      sum_r2 += double(dist * dist) / double(r * r);
    }
  }
  // Uniform by area in a unit disc: E[r^2] = 1/2.
  EXPECT_NEAR(sum_r2 / double(a.size()), 0.5, 0.01);
  const auto b = fv::generate_ray_samples(ps, vis, spp, 1234, 200);
  EXPECT_EQ(0, std::memcmp(a.sample_px.data(), b.sample_px.data(), a.size() * sizeof(glm::vec2)));
  // A point's samples do not depend on which other points are visible: every
  // third visible point alone (a different list, each point at another place in
  // it) gets exactly the samples it got among all of them.
  fv::VisiblePoints third;
  for (std::size_t v = 0; v < vis.size(); v += 3) {
    third.point_index.push_back(vis.point_index[v]);
    third.screen_px.push_back(vis.screen_px[v]);
  }
  ASSERT_GT(third.size(), 10u);
  const auto c = fv::generate_ray_samples(ps, third, spp, 1234, 200);
  ASSERT_EQ(c.size(), third.size() * spp);
  for (std::size_t t = 0; t < third.size(); ++t) {
    for (int s = 0; s < spp; ++s) {
      const std::size_t o = t * spp + std::size_t(s), full = 3 * t * spp + std::size_t(s);
      ASSERT_EQ(c.point_index[o], a.point_index[full]) << t << "," << s;
      const glm::vec2 alone = c.sample_px[o], among_all = a.sample_px[full];
      ASSERT_TRUE(alone == among_all) << "point " << third.point_index[t] << " sample " << s << ": (" << alone.x << ", "
                                      << alone.y << ") among every third point, (" << among_all.x << ", "
                                      << among_all.y << ") among all";
    }
  }
  // The seed does change them.
  EXPECT_NE(fv::unit_disc_sample(1234, 77, 3), fv::unit_disc_sample(1235, 77, 3));
  EXPECT_THROW(fv::generate_ray_samples(ps, vis, 0, 1, 200), std::invalid_argument);
}

// The pixel filter's offsets follow the filter (ray_samples.hpp): box uniform
// over the pixel; bspline2 the quadratic B-spline around the pixel's centre —
// on (-1, 2), mean 1/2, variance 3/12, P(< 0) = P(> 1) = 1/6 per axis, the two
// axes independent — and box's offsets are the default's.
TEST(RaySamples, PixelJitterFollowsThePixelFilter) {
  constexpr int kN = 40000;
  double mean[2] = {}, var[2] = {}, below0[2] = {}, above1[2] = {}, cov = 0.0;
  for (int i = 0; i < kN; ++i) {
    const std::uint64_t pixel = std::uint64_t(i / 8), sample = std::uint32_t(i % 8);
    const glm::vec2 b = fv::pixel_jitter(pixel, std::uint32_t(sample), 7, fv::PixelFilter::box);
    ASSERT_EQ(b, fv::pixel_jitter(pixel, std::uint32_t(sample), 7));
    ASSERT_GE(b.x, 0.0f);
    ASSERT_LT(b.x, 1.0f);
    ASSERT_GE(b.y, 0.0f);
    ASSERT_LT(b.y, 1.0f);
    const glm::vec2 q = fv::pixel_jitter(pixel, std::uint32_t(sample), 7, fv::PixelFilter::bspline2);
    for (int a = 0; a < 2; ++a) {
      const double v = double(q[a]);
      ASSERT_GT(v, -1.0);
      ASSERT_LT(v, 2.0);
      mean[a] += v;
      var[a] += (v - 0.5) * (v - 0.5);
      below0[a] += v < 0.0;
      above1[a] += v > 1.0;
    }
    cov += (double(q.x) - 0.5) * (double(q.y) - 0.5);
  }
  // Tolerances: about 5 standard errors of each estimate at kN samples.
  for (int a = 0; a < 2; ++a) {
    EXPECT_NEAR(mean[a] / kN, 0.5, 0.013) << a;
    EXPECT_NEAR(var[a] / kN, 0.25, 0.006) << a;
    EXPECT_NEAR(below0[a] / kN, 1.0 / 6.0, 0.01) << a;
    EXPECT_NEAR(above1[a] / kN, 1.0 / 6.0, 0.01) << a;
  }
  EXPECT_NEAR(cov / kN, 0.0, 0.007);
  fv::PixelFilter f = fv::PixelFilter::box;
  EXPECT_TRUE(fv::parse_pixel_filter("bspline2", &f));
  EXPECT_EQ(f, fv::PixelFilter::bspline2);
  EXPECT_STREQ(fv::pixel_filter_name(f), "bspline2");
  EXPECT_TRUE(fv::parse_pixel_filter("box", &f));
  EXPECT_EQ(f, fv::PixelFilter::box);
  EXPECT_FALSE(fv::parse_pixel_filter("gaussian", &f));
  EXPECT_EQ(f, fv::PixelFilter::box);  // untouched
}

// A pixel-grid point's rays cover its own screen pixel uniformly, exactly
// where the full render puts that pixel's (the same pixel_jitter), whatever
// point index it has and wherever the gaze put the canvas.
TEST(RaySamples, PixelGridPointsSampleTheirOwnPixelAsTheFullRenderDoes) {
  auto d = fv::DisplayModel::from_fov(200, 160, 90.0);
  d.scale = 4.0;  // the grid edge inside the screen
  const fv::PointSet ps = fv::generate_point_set(d, 4);
  const auto vis = fv::select_visible_points(ps, fv::map_gaze(200, 160, {90.6f, 70.2f}));
  const int spp = 4;
  const auto samples = fv::generate_ray_samples(ps, vis, spp, 99, 200);
  std::size_t grid = 0, disc = 0;
  double sum_x = 0.0, sum_y = 0.0;
  for (std::size_t v = 0; v < vis.size(); ++v) {
    const bool on_grid = ps.on_pixel_grid(vis.point_index[v]);
    grid += on_grid;
    disc += !on_grid;
    if (!on_grid) continue;
    const int x = int(vis.screen_px[v].x), y = int(vis.screen_px[v].y);
    for (int s = 0; s < spp; ++s) {
      const glm::vec2 p = samples.sample_px[v * spp + std::size_t(s)];
      ASSERT_EQ(p, glm::vec2(float(x), float(y)) + fv::pixel_jitter(std::uint64_t(y) * 200 + std::uint64_t(x), std::uint32_t(s), 99));
      // The closed square: x + u with u < 1 can round up to x + 1 in float, as in the full render.
      ASSERT_GE(p.x, float(x));
      ASSERT_LE(p.x, float(x + 1));
      ASSERT_GE(p.y, float(y));
      ASSERT_LE(p.y, float(y + 1));
      sum_x += double(p.x) - x;
      sum_y += double(p.y) - y;
    }
  }
  ASSERT_GT(grid, 1000u);
  ASSERT_GT(disc, 1000u);
  EXPECT_NEAR(sum_x / double(grid * spp), 0.5, 0.01);  // uniform over the pixel
  EXPECT_NEAR(sum_y / double(grid * spp), 0.5, 0.01);
}
