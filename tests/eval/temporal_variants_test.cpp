// The lab's foveated views (fovea-eval motion and accuracy) apply the options' content
// density, at the display's exposure, as `fovea render` does: every temporal variant's view
// settings carry it, and it stays off when the options leave it off.
#include <gtest/gtest.h>

#include <eval/temporal_variants.hpp>

namespace {

using namespace foveart;

constexpr eval::TemporalVariant kVariants[] = {eval::TemporalVariant::off, eval::TemporalVariant::restart,
                                               eval::TemporalVariant::image, eval::TemporalVariant::rays,
                                               eval::TemporalVariant::rays_kept};

TEST(TemporalVariants, EveryVariantAppliesTheOptionsContentDensityAtTheDisplaysExposure) {
  render_view::RenderOptions o;
  o.content_contrast = 0.25;
  o.content_rays = 0.5;
  for (const eval::TemporalVariant variant : kVariants) {
    SCOPED_TRACE(eval::temporal_variant_name(variant));
    const foveation::ViewSettings vs =
        eval::variant_view_settings(variant, eval::variant_settings(o, /*mean_while_young=*/false, 0.375f));
    EXPECT_FLOAT_EQ(vs.content_density.full_contrast, 0.25f);
    EXPECT_FLOAT_EQ(vs.content_density.rays_contrast, 0.5f);
    EXPECT_FLOAT_EQ(vs.content_density.exposure, 0.375f);
    EXPECT_TRUE(vs.content_density.enabled());
  }
  const foveation::ViewSettings off =
      eval::variant_view_settings(eval::TemporalVariant::image, eval::variant_settings({}, false, 0.375f));
  EXPECT_FALSE(off.content_density.enabled()) << "off unless the options ask for it";
}

}  // namespace
