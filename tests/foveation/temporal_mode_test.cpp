// The one temporal choice: names round-trip, anything else is refused, and each mode
// fixes the TAA, its history, the jitter and the pixel filter together.
#include <gtest/gtest.h>

#include "foveation/temporal_mode.hpp"
#include "foveation/view_settings.hpp"

namespace foveart::foveation {
namespace {

TEST(TemporalMode, NamesRoundTripAndOthersAreRefused) {
  for (TemporalMode m : {TemporalMode::off, TemporalMode::image, TemporalMode::rays}) {
    TemporalMode parsed = TemporalMode::off;
    ASSERT_TRUE(parse_temporal_mode(temporal_mode_name(m), &parsed)) << temporal_mode_name(m);
    EXPECT_EQ(parsed, m);
  }
  TemporalMode untouched = TemporalMode::image;
  for (const char* bad : {"", "auto", "on", "true", "reproject", "ray_cache", "Rays", "rays "}) {
    EXPECT_FALSE(parse_temporal_mode(bad, &untouched)) << '"' << bad << '"';
    EXPECT_EQ(untouched, TemporalMode::image);
  }
}

TEST(TemporalMode, EachModeFixesHistoryJitterAndPixelFilter) {
  const ViewSettings off = temporal_view_settings(TemporalMode::off, 2, 7);
  EXPECT_EQ(off.temporal, TemporalMode::off);
  EXPECT_FALSE(off.new_jitter_each_frame);
  EXPECT_EQ(off.pixel_filter, PixelFilter::box);

  const ViewSettings image = temporal_view_settings(TemporalMode::image, 2, 7);
  EXPECT_EQ(image.temporal, TemporalMode::image);
  EXPECT_TRUE(image.new_jitter_each_frame);
  EXPECT_EQ(image.pixel_filter, PixelFilter::box);

  const ViewSettings rays = temporal_view_settings(TemporalMode::rays, 2, 7);
  EXPECT_EQ(rays.temporal, TemporalMode::rays);
  EXPECT_TRUE(rays.new_jitter_each_frame);
  EXPECT_EQ(rays.pixel_filter, PixelFilter::bspline2);

  for (const ViewSettings& v : {off, image, rays}) {
    EXPECT_EQ(v.rays_per_point, 2);
    EXPECT_EQ(v.sample_seed, 7U);
    EXPECT_FALSE(v.temporal_options.mean_while_young) << "an evaluation option, never the product's";
  }
}

}  // namespace
}  // namespace foveart::foveation
