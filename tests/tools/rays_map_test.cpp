// `fovea render --out`'s rays map (tools/fovea/rays_map.hpp): the colour of a point's rays,
// each pixel from its nearest coloured point, and the frame's luminance as its shade.
#include <rays_map.hpp>

#include <foveation/gaze_mapping.hpp>

#include <gtest/gtest.h>

#include <cstdint>

#include "threaded/small_view.hpp"

namespace foveart::fovea {
namespace {

void expect_rgb(const float* got, glm::vec3 want, const char* what, int x, int y) {
  for (int c = 0; c < 3; ++c)
    ASSERT_NEAR(got[c], want[c], 1e-6f) << what << " at " << x << "," << y << " channel " << c;
}

foveation::ImageRgb flat_frame(int w, int h, float radiance) {
  foveation::ImageRgb img;
  img.width_px = w;
  img.height_px = h;
  img.rgb.assign(std::size_t(w) * std::size_t(h) * 3, radiance);
  return img;
}

TEST(RaysMap, ColoursRunFromOneRayToAllOnALogScaleAndFilledIsGrey) {
  EXPECT_EQ(rays_colour(0, 16), kFilledRgb);
  EXPECT_EQ(rays_colour(1, 16), kOneRayRgb);
  EXPECT_EQ(rays_colour(16, 16), kAllRaysRgb);
  EXPECT_EQ(rays_colour(1, 1), kAllRaysRgb) << "one ray per point is all of them";
  const glm::vec3 half = rays_colour(4, 16);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(half[c], 0.5f * (kOneRayRgb[c] + kAllRaysRgb[c]), 1e-6f);
  EXPECT_EQ(rays_colour(40, 16), kAllRaysRgb) << "more than rays_per_point saturates";
}

TEST(RaysMap, EachPixelTakesItsNearestColouredPointShadedByTheFrame) {
  constexpr int kW = 64, kH = 48;
  const auto tables = foveation::small_view::tables(kW, kH, 4.0, 1, foveation::InterpMethod::nearest, 4);
  const std::size_t n = tables->points.size();
  foveation::TracedPoints traced;
  traced.colors.rgba.assign(n, foveation::Rgba{0.5f, 0.5f, 0.5f, 1.0f});
  traced.rays_cast.resize(n);
  for (std::size_t i = 0; i < n; ++i) traced.rays_cast[i] = std::uint16_t(i % 3 == 0 ? 0 : i % 3 == 1 ? 1 : 8);
  foveation::FrameHandOff frame;
  frame.traced = &traced;
  frame.mapping = foveation::map_gaze(kW, kH, {kW / 2.0f, kH / 2.0f});
  const foveation::NeighborTable& nt = tables->neighbors;
  auto nearest = [&](int x, int y, int j) {
    return nt.neighbor(frame.mapping.canvas_index(std::size_t(x), std::size_t(y), std::size_t(nt.width_px())), j);
  };

  // A white frame shows the colours at full strength; a black one at 0.3.
  for (const auto& [radiance, shade] : {std::pair{1.0f, 1.0f}, std::pair{0.0f, 0.3f}}) {
    const foveation::ImageRgb map = rays_map(*tables, frame, flat_frame(kW, kH, radiance), foveation::kClampOnly, 8);
    ASSERT_EQ(map.width_px, kW);
    ASSERT_EQ(map.height_px, kH);
    for (int y = 0; y < kH; ++y)
      for (int x = 0; x < kW; ++x)
        expect_rgb(map.at(x, y), shade * rays_colour(traced.rays_cast[nearest(x, y, 0)], 8), "map", x, y);
  }

  // A pixel whose nearest point has no colour takes the next one's; with none in reach, black.
  const std::uint32_t first = nearest(0, 0, 0), second = nearest(0, 0, 1);
  ASSERT_NE(first, second);
  traced.colors.rgba[first].a = 0.0f;
  traced.rays_cast[second] = 8;
  expect_rgb(rays_map(*tables, frame, flat_frame(kW, kH, 1.0f), foveation::kClampOnly, 8).at(0, 0), kAllRaysRgb,
             "the next point", 0, 0);
  for (foveation::Rgba& c : traced.colors.rgba) c.a = 0.0f;
  expect_rgb(rays_map(*tables, frame, flat_frame(kW, kH, 1.0f), foveation::kClampOnly, 8).at(kW / 2, kH / 2),
             kNoPointRgb, "no point", kW / 2, kH / 2);
}

TEST(RaysMap, AFrameWithoutPointsOnTheHostIsBlack) {
  const auto tables = foveation::small_view::tables(32, 24, 4.0, 1, foveation::InterpMethod::nearest, 1);
  foveation::FrameHandOff nothing;  // traced on the device: no points on the host
  const foveation::ImageRgb map = rays_map(*tables, nothing, flat_frame(32, 24, 1.0f), foveation::kClampOnly, 4);
  for (float v : map.rgb) ASSERT_EQ(v, 0.0f);
  const foveation::TracedPoints planned;  // FoveatedView::plan's hand-off: a frame with no points of its own
  nothing.traced = &planned;
  for (float v : rays_map(*tables, nothing, flat_frame(32, 24, 1.0f), foveation::kClampOnly, 4).rgb) ASSERT_EQ(v, 0.0f);
}

}  // namespace
}  // namespace foveart::fovea
