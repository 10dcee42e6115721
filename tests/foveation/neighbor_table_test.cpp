// The per-canvas-pixel k nearest points equal brute force, ties included.
#include <gtest/gtest.h>

#include <cstddef>
#include <cstring>
#include <functional>
#include <numeric>
#include <unistd.h>
#include <glm/geometric.hpp>

#include <algorithm>
#include <random>
#include <utility>
#include <vector>

#include "foveation/gaze_mapping.hpp"
#include "foveation/neighbor_table.hpp"
#include "foveation/point_set.hpp"
#include "test_executor.hpp"

namespace fv = foveart::foveation;

namespace {

// The k nearest points of pixel (x, y)'s centre by (squared distance, index): each
// point against the worst of the k best so far (plain loops: the sanitizer
// builds compile tests unoptimised).
std::vector<std::uint32_t> brute_force(const fv::PointSet& ps, int x, int y, int k) {
  std::vector<std::pair<double, std::uint32_t>> best;  // ascending, at most k
  best.reserve(std::size_t(k) + 1);
  const glm::vec2* p = ps.position_px.data();
  const double cx = x + 0.5, cy = y + 0.5;
  for (std::uint32_t i = 0, n = std::uint32_t(ps.size()); i < n; ++i) {
    const double dx = double(p[i].x) - cx, dy = double(p[i].y) - cy;
    const double d2 = dx * dx + dy * dy;
    if (int(best.size()) == k && !(d2 < best.back().first)) continue;  // equal distance: the lower index came first
    std::size_t at = best.size();
    while (at > 0 && d2 < best[at - 1].first) --at;
    best.insert(best.begin() + std::ptrdiff_t(at), {d2, i});
    if (int(best.size()) > k) best.pop_back();
  }
  std::vector<std::uint32_t> out;
  for (const auto& b : best) out.push_back(b.second);
  return out;
}

// Integer lattice: every pixel centre is equidistant from 4, 8, 12... points.
fv::PointSet lattice(int w, int h, int step) {
  fv::PointSet ps;
  ps.canvas_width_px = w;
  ps.canvas_height_px = h;
  for (int y = 0; y < h; y += step) {
    for (int x = 0; x < w; x += step) {
      ps.position_px.emplace_back(float(x), float(y));
      ps.radius_px.push_back(0.5f * float(step));
    }
  }
  // Shuffle so index order is not geometric order: ties must still go by index.
  std::mt19937 rng(9);
  std::vector<std::size_t> order(ps.size());
  std::iota(order.begin(), order.end(), 0);
  std::shuffle(order.begin(), order.end(), rng);
  fv::PointSet out = ps;
  for (std::size_t i = 0; i < order.size(); ++i) out.position_px[i] = ps.position_px[order[i]];
  return out;
}

}  // namespace

TEST(NeighborTable, EqualsBruteForceOnRandomPixels) {
  auto d = fv::DisplayModel::from_thesis(200, 240, 0.85);
  d.scale = 3.0;
  const auto ps = fv::generate_point_set(d, 1);
  for (int k : {1, 5, 20}) {
    const auto table = fv::NeighborTable::build(ps, k, fv::test::executor());
    EXPECT_EQ(table.width_px(), 400);
    EXPECT_EQ(table.height_px(), 480);
    EXPECT_EQ(table.bytes(), 400u * 480u * std::size_t(k) * 3u + 1u);
    std::mt19937 rng(k);
    for (int n = 0; n < 800; ++n) {
      const int x = int(rng() % 400);
      const int y = int(rng() % 480);
      const auto want = brute_force(ps, x, y, k);
      const std::size_t pixel = std::size_t(y) * 400 + std::size_t(x);
      for (int j = 0; j < k; ++j) {
        ASSERT_EQ(table.neighbor(pixel, j), want[std::size_t(j)]) << "pixel " << x << "," << y << " j=" << j;
      }
    }
  }
}

TEST(NeighborTable, ExactTiesGoToTheLowerIndex) {
  const auto ps = lattice(64, 48, 3);  // pixel centres at .5: many exact ties
  const auto table = fv::NeighborTable::build(ps, 12, fv::test::executor());
  for (int y = 0; y < 48; ++y) {
    for (int x = 0; x < 64; ++x) {
      const auto want = brute_force(ps, x, y, 12);
      for (int j = 0; j < 12; ++j) {
        ASSERT_EQ(table.neighbor(std::size_t(y) * 64 + std::size_t(x), j), want[std::size_t(j)])
            << "pixel " << x << "," << y << " j=" << j;
      }
    }
  }
}

TEST(NeighborTable, IndicesValidAndGazeNeverReadsOutsideTheCanvas) {
  auto d = fv::DisplayModel::from_thesis(120, 100, 0.85);
  d.scale = 3.0;
  const auto ps = fv::generate_point_set(d, 2);
  const auto table = fv::NeighborTable::build(ps, 8, fv::test::executor());
  for (std::size_t p = 0; p < table.pixel_count(); ++p) {
    for (int j = 0; j < 8; ++j) ASSERT_LT(table.neighbor(p, j), ps.size());
  }
  // Corners, edges, centre and off-screen gazes: every screen pixel maps inside.
  const std::vector<glm::vec2> gazes = {{0, 0},     {120, 0},   {0, 100},  {120, 100}, {60, 50},  {0, 50},
                                        {119.6f, 99.6f}, {-50, -50}, {500, 20}, {60, 1e9f}, {0.49f, 0.51f}};
  for (const auto g : gazes) {
    const auto m = fv::map_gaze(120, 100, g);
    for (int sy : {0, 99}) {
      for (int sx : {0, 119}) {
        const int cx = sx + m.canvas_from_screen_x_px;
        const int cy = sy + m.canvas_from_screen_y_px;
        EXPECT_GE(cx, 0);
        EXPECT_GE(cy, 0);
        EXPECT_LT(cx, table.width_px());
        EXPECT_LT(cy, table.height_px());
      }
    }
  }
}

TEST(NeighborTable, RejectsBadK) {
  const auto ps = lattice(16, 16, 4);
  EXPECT_THROW(fv::NeighborTable::build(ps, 0, fv::test::executor()), std::invalid_argument);
  EXPECT_THROW(fv::NeighborTable::build(ps, 21, fv::test::executor()), std::invalid_argument);
  EXPECT_THROW(fv::NeighborTable::build(lattice(4, 4, 2), 5, fv::test::executor()), std::invalid_argument);  // 4 points < k
}

namespace {

// Dimensions whose product wraps size_t: 2^30 x 2^30 pixels x 16 neighbours x
// 3 bytes is 3 x 2^64, which wrapped to 0, so a 1-byte buffer used to match.
TEST(NeighborTable, PackedDimensionsThatWrapTheSizeAreRejected) {
  EXPECT_THROW(fv::NeighborTable::from_packed(1 << 30, 1 << 30, 16, std::vector<std::uint8_t>(1)),
               std::invalid_argument);
  EXPECT_THROW(fv::NeighborTable::from_packed(4, 4, 0, std::vector<std::uint8_t>(1)), std::invalid_argument);
  EXPECT_NO_THROW(fv::NeighborTable::from_packed(4, 2, 3, std::vector<std::uint8_t>(4 * 2 * 3 * 3 + 1)));
}

}  // namespace
