// The tile-local gather layout (gather_layout.hpp): every 1-byte tap names the
// same point as the NeighborTable, dense tiles split into smaller blocks, bad
// layouts are detected, and the AVX2 and portable gathers agree with a plain
// double-precision reference on canvases that are not multiples of the tile.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <utility>

#include "foveation/gather.hpp"
#include "foveation/gather_layout.hpp"
#include "foveation/interpolation_table.hpp"
#include "interpolation_fixture.hpp"
#include "interpolation_test_util.hpp"
#include "test_executor.hpp"

namespace foveart::foveation {
namespace {

// Uniform random points, `per_px` per pixel on average, on a w x h canvas.
PointSet random_points(int w, int h, double per_px, std::uint32_t seed) {
  PointSet ps;
  ps.canvas_width_px = w;
  ps.canvas_height_px = h;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> ux(0.0f, float(w)), uy(0.0f, float(h));
  const auto n = std::size_t(per_px * w * h);
  for (std::size_t i = 0; i < n; ++i) {
    ps.position_px.push_back({ux(rng), uy(rng)});
    ps.radius_px.push_back(0.5f);
  }
  return ps;
}

using test::opts;

// Point named by tap j of canvas pixel (x, y) through the layout.
std::uint32_t layout_point(const GatherLayout& l, int x, int y, int j) {
  const int tx = x / kGatherTilePx, ty = y / kGatherTilePx;
  const std::size_t tile = std::size_t(ty) * std::size_t(l.tiles_x()) + std::size_t(tx);
  const int bs = kGatherTilePx >> l.tile_level[tile];
  const int tw = std::min(kGatherTilePx, l.width_px - tx * kGatherTilePx);
  const int nbx = (tw + bs - 1) / bs;
  const int lx = x - tx * kGatherTilePx, ly = y - ty * kGatherTilePx;
  const std::size_t b = l.tile_first_block[tile] + std::size_t((ly / bs) * nbx + lx / bs);
  const std::uint8_t s = l.slot[tile_ordinal(l.width_px, l.height_px, x, y) * std::size_t(l.k) + std::size_t(j)];
  return l.palette[l.block_palette[b] + s];
}

TEST(GatherLayout, TileOrdinalIsAPermutation) {
  for (auto [w, h] : {std::pair{64, 48}, std::pair{61, 45}, std::pair{5, 3}, std::pair{17, 9}}) {
    std::vector<int> seen(std::size_t(w * h), 0);
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        const std::size_t o = tile_ordinal(w, h, x, y);
        ASSERT_LT(o, seen.size()) << w << "x" << h;
        ++seen[o];
      }
    }
    EXPECT_TRUE(std::all_of(seen.begin(), seen.end(), [](int c) { return c == 1; })) << w << "x" << h;
  }
}

TEST(GatherLayout, EveryTapNamesTheNeighbourTablesPoint) {
  // 61 x 45: partial tiles at the right and bottom; 0.3 points per pixel.
  const auto ps = random_points(61, 45, 0.3, 3);
  const auto nt = NeighborTable::build(ps, 20, test::executor());
  for (int k : {1, 7, 20}) {
    const auto l = build_gather_layout(nt, k, test::executor());
    EXPECT_EQ(gather_layout_error(l, 61, 45, k, ps.size()), "");
    for (int y = 0; y < 45; ++y) {
      for (int x = 0; x < 61; ++x) {
        for (int j = 0; j < k; ++j) {
          ASSERT_EQ(layout_point(l, x, y, j), nt.neighbor(std::size_t(y) * 61 + std::size_t(x), j))
              << "k " << k << " pixel " << x << "," << y << " tap " << j;
        }
      }
    }
    // Sparse points: every tile fits one palette.
    EXPECT_TRUE(std::all_of(l.tile_level.begin(), l.tile_level.end(), [](std::uint8_t v) { return v == 0; }));
  }
}

TEST(GatherLayout, DenseTilesSplitIntoSmallerBlocks) {
  // 8 points per pixel: an 8 x 8 tile alone holds ~512 points (> 256).
  const auto ps = random_points(20, 18, 8.0, 4);
  const auto nt = NeighborTable::build(ps, 20, test::executor());
  Executor one_thread(1), three_threads(3);
  const auto a = build_gather_layout(nt, 20, one_thread);
  const auto b = build_gather_layout(nt, 20, three_threads);
  EXPECT_EQ(gather_layout_error(a, 20, 18, 20, ps.size()), "");
  EXPECT_TRUE(std::any_of(a.tile_level.begin(), a.tile_level.end(), [](std::uint8_t v) { return v > 0; }));
  for (std::size_t i = 0; i + 1 < a.block_palette.size(); ++i) EXPECT_LE(a.block_palette[i + 1] - a.block_palette[i], 256u);
  for (int y = 0; y < 18; ++y) {
    for (int x = 0; x < 20; ++x) {
      for (int j = 0; j < 20; ++j) ASSERT_EQ(layout_point(a, x, y, j), nt.neighbor(std::size_t(y) * 20 + std::size_t(x), j));
    }
  }
  // Identical for any thread count.
  EXPECT_EQ(a.slot, b.slot);
  EXPECT_EQ(a.palette, b.palette);
  EXPECT_EQ(a.tile_level, b.tile_level);
}

TEST(GatherLayout, InconsistentLayoutsAreReported) {
  const auto ps = random_points(24, 16, 0.5, 5);
  const auto nt = NeighborTable::build(ps, 10, test::executor());
  const auto good = build_gather_layout(nt, 10, test::executor());
  ASSERT_EQ(gather_layout_error(good, 24, 16, 10, ps.size()), "");
  EXPECT_NE(gather_layout_error(good, 24, 16, 9, ps.size()), "");   // other k
  EXPECT_NE(gather_layout_error(good, 16, 24, 10, ps.size()), "");  // other canvas
  auto bad_slot = good;
  bad_slot.slot[37] = 255;  // no palette here is that large
  EXPECT_NE(gather_layout_error(bad_slot, 24, 16, 10, ps.size()).find("slot"), std::string::npos);
  auto bad_point = good;
  bad_point.palette[3] = std::uint32_t(ps.size());
  EXPECT_NE(gather_layout_error(bad_point, 24, 16, 10, ps.size()).find("point"), std::string::npos);
  auto bad_level = good;
  bad_level.tile_level[1] = 1;  // block count no longer matches
  EXPECT_NE(gather_layout_error(bad_level, 24, 16, 10, ps.size()), "");
  auto short_slots = good;
  short_slots.slot.pop_back();
  EXPECT_NE(gather_layout_error(short_slots, 24, 16, 10, ps.size()), "");
  EXPECT_THROW(build_gather_layout(nt, 11, test::executor()), std::invalid_argument);
}

// Range of the colours of taps of canvas pixels [x0, x1) x [y0, y1).
void tap_range(const NeighborTable& nt, const InterpolationTable& t, const PointColors& c, int x0, int x1, int y0,
               int y1, double lo[3], double hi[3]) {
  for (int y = y0; y < y1; ++y) {
    for (int x = x0; x < x1; ++x) {
      const std::size_t cp = std::size_t(y) * std::size_t(t.width_px) + std::size_t(x);
      for (int j = 0; j < t.taps(); ++j) {
        const Rgba& p = c.rgba[nt.neighbor(cp, j)];
        const double ch[3] = {p.r, p.g, p.b};
        for (int i = 0; i < 3; ++i) lo[i] = std::min(lo[i], ch[i]), hi[i] = std::max(hi[i], ch[i]);
      }
    }
  }
}

// Reference gather in double: Σ w c / Σ w (normalised tables); RBF clamped to
// the taps' range, or to the range of every tap of the pixel's gather block
// (the tile's 8 >> level square holding the pixel, cut at the canvas edge).
// *abs_sum: Σ|w|, the scale of the float accumulation error (colours in [0, 1]).
std::array<double, 3> reference_pixel(const NeighborTable& nt, const InterpolationTable& t, const PointColors& c,
                                      std::size_t cp, RbfClamp clamp, double* abs_sum) {
  double acc[3] = {0, 0, 0}, s = 0, lo[3] = {1e30, 1e30, 1e30}, hi[3] = {-1e30, -1e30, -1e30};
  *abs_sum = 0;
  for (int j = 0; j < t.taps(); ++j) {
    const double w = t.weight(cp, j);
    const Rgba& p = c.rgba[nt.neighbor(cp, j)];
    const double ch[3] = {p.r, p.g, p.b};
    s += w;
    *abs_sum += std::abs(w);
    for (int i = 0; i < 3; ++i) acc[i] += w * ch[i];
  }
  const int x = int(cp % std::size_t(t.width_px)), y = int(cp / std::size_t(t.width_px));
  if (clamp == RbfClamp::taps) tap_range(nt, t, c, x, x + 1, y, y + 1, lo, hi);
  if (clamp == RbfClamp::block) {
    const int tx = x / kGatherTilePx, ty = y / kGatherTilePx;
    const int bs = kGatherTilePx >> t.layout.tile_level[std::size_t(ty) * std::size_t(t.layout.tiles_x()) + std::size_t(tx)];
    const int bx = tx * kGatherTilePx + (x - tx * kGatherTilePx) / bs * bs;
    const int by = ty * kGatherTilePx + (y - ty * kGatherTilePx) / bs * bs;
    tap_range(nt, t, c, bx, std::min(bx + bs, t.width_px), by, std::min(by + bs, t.height_px), lo, hi);
  }
  std::array<double, 3> r{};
  for (int i = 0; i < 3; ++i) {
    r[std::size_t(i)] = t.normalized() ? acc[i] / s : acc[i];
    if (t.is_rbf() && clamp != RbfClamp::off) r[std::size_t(i)] = std::clamp(r[std::size_t(i)], lo[i], hi[i]);
  }
  return r;
}

TEST(GatherLayout, SimdAndPortableGathersMatchTheReference) {
  const auto ps = random_points(61, 45, 0.4, 6);
  const auto nt = NeighborTable::build(ps, 20, test::executor());
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<float> rgb(ps.size() * 3);
  for (float& v : rgb) v = u(rng);
  std::vector<std::uint8_t> valid(ps.size(), 1);
  const auto all_valid = point_colors_from_all(rgb);
  for (std::size_t i = 0; i < valid.size(); i += 11) valid[i] = 0;
  const auto some_invalid = point_colors_from_all(rgb, valid);
  // A 29 x 21 screen at an offset that is not a multiple of the tile.
  GazeMapping map;
  map.screen_width_px = 29, map.screen_height_px = 21;
  map.canvas_from_screen_x_px = 13, map.canvas_from_screen_y_px = 11;
  for (auto [m, clamp] : {std::pair{InterpMethod::msm, RbfClamp::block}, std::pair{InterpMethod::rbf, RbfClamp::block},
                          std::pair{InterpMethod::rbf, RbfClamp::taps}, std::pair{InterpMethod::rbf, RbfClamp::off}}) {
    // float accumulation: MSM is convex; RBF weights are signed. Clamped results
    // stay in [0, 1]; unclamped ones reach ~30 here, so their error is taken
    // per unit of Σ|w| (the scale of the accumulation error).
    const double tol = m == InterpMethod::msm ? 2e-6 : 1e-5;
    for (int k : {5, 7, 10, 15, 20}) {
      for (auto prec : {WeightPrecision::f16, WeightPrecision::f32}) {
        const auto t = build_interpolation_table(ps, nt, opts(m, k), test::executor(), prec);
        for (unsigned threads : {1u, 2u, 3u}) {
          Executor executor(threads);
          GatherOptions simd, portable;
          simd.rbf_clamp = portable.rbf_clamp = clamp;
          portable.simd = false;
          ImageRgb a, b;
          const auto sa = gather(nt, t, all_valid, map, a, executor, simd);
          gather(nt, t, all_valid, map, b, executor, portable);
          EXPECT_EQ(sa.renormalized + sa.nearest_valid + sa.fallback, 0u);
          double worst = 0;
          for (int y = 0; y < 21; ++y) {
            for (int x = 0; x < 29; ++x) {
              const std::size_t cp = std::size_t(y + 11) * 61 + std::size_t(x + 13);
              double abs_sum = 0;
              const auto r = reference_pixel(nt, t, all_valid, cp, clamp, &abs_sum);
              for (int i = 0; i < 3; ++i) {
                const double scale = clamp == RbfClamp::off ? abs_sum : 1.0;
                worst = std::max(worst, std::abs(double(a.at(x, y)[i]) - r[std::size_t(i)]) / scale);
                worst = std::max(worst, std::abs(double(b.at(x, y)[i]) - r[std::size_t(i)]) / scale);
              }
            }
          }
          EXPECT_LT(worst, tol) << method_name(m) << " k " << k << " threads " << threads << " clamp " << int(clamp);
          // Invalid points: both kernels take the same documented slow path.
          const auto ia = gather(nt, t, some_invalid, map, a, executor, simd);
          const auto ib = gather(nt, t, some_invalid, map, b, executor, portable);
          EXPECT_GT(ia.renormalized, 0u);
          EXPECT_EQ(ia.renormalized, ib.renormalized);
          EXPECT_EQ(ia.nearest_valid, ib.nearest_valid);
          for (int y = 0; y < 21; ++y) {
            for (int x = 0; x < 29; ++x) {
              double abs_sum = 0;
              reference_pixel(nt, t, all_valid, std::size_t(y + 11) * 61 + std::size_t(x + 13), clamp, &abs_sum);
              for (int i = 0; i < 3; ++i) {
                ASSERT_TRUE(std::isfinite(a.at(x, y)[i]));
                ASSERT_NEAR(a.at(x, y)[i], b.at(x, y)[i], tol * (clamp == RbfClamp::off ? abs_sum : 1.0))
                    << method_name(m) << " k " << k;
              }
            }
          }
        }
      }
    }
  }
}

TEST(GatherOptions, RbfClampNamesRoundTrip) {
  for (RbfClamp c : {RbfClamp::off, RbfClamp::taps, RbfClamp::block}) EXPECT_EQ(parse_rbf_clamp(rbf_clamp_name(c)), c);
  EXPECT_EQ(parse_rbf_clamp("Block"), std::nullopt);
  EXPECT_EQ(parse_rbf_clamp(""), std::nullopt);
  EXPECT_EQ(GatherOptions{}.rbf_clamp, RbfClamp::block);  // the documented default
}

}  // namespace
}  // namespace foveart::foveation
