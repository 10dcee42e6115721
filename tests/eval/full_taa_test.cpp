// The full render with a foveated view's temporal history (eval/full_taa.hpp):
// its first frame is the plain full render at the view's seed, each frame
// draws new jitter (seed + frame index, as a foveated view with TAA), it
// blends with the foveated view's weight, and at a still view its error
// against a converged render falls as frames accumulate.
#include <render_view/render_options.hpp>
#include "small_scene.hpp"
#include <eval/full_taa.hpp>
#include <metrics/image_metrics.hpp>
#include <eval/taa_modes.hpp>

#include <engine/gltf_loader.hpp>
#include <engine/render.hpp>
#include <engine/tracer.hpp>
#include <foveation/executor.hpp>

#include <gtest/gtest.h>

#include <cmath>

using namespace foveart;

namespace {

using eval_test::SmallScene;

// PSNR of two linear images in display values over all pixels and channels.
double display_psnr(const foveation::ImageRgb& a, const foveation::ImageRgb& b) {
  const foveation::ImageRgb da = metrics::display_encode(a), db = metrics::display_encode(b);
  double se = 0.0;
  for (std::size_t i = 0; i < da.rgb.size(); ++i) se += std::pow(double(da.rgb[i]) - double(db.rgb[i]), 2.0);
  return 10.0 * std::log10(double(da.rgb.size()) / se);
}

foveation::ImageRgb full_render(SmallScene& s, int spp, std::uint64_t seed, foveation::Executor& executor) {
  engine::RenderSettings rs;
  rs.spp = spp;
  rs.seed = seed;
  foveation::ImageRgb image;
  EXPECT_EQ(engine::render_full(&foveart_engine_trace_rays, s.tracer.get(), s.view, rs, &image, executor).status,
            FOVEART_RESULT_SUCCESS);
  return image;
}

}  // namespace

TEST(PricelistFullTaa, FirstFrameIsTheFullRenderThenNewJitterBlendedAsTheFoveatedView) {
  SmallScene s(32, 36);
  foveation::Executor executor(2);
  const foveation::ViewSettings vs =
      eval::taa_view_settings("reproject", 2, 7, foveation::PixelFilter::box, /*taa_mean_while_young=*/false);
  eval::FullTaaRender r(vs);
  EXPECT_EQ(r.frame_seed(0), 7u);
  EXPECT_EQ(r.frame_seed(5), 12u);  // new jitter each frame, as FoveatedView's sample_seed + frame_index
  const glm::vec2 gaze(16, 18);
  ASSERT_EQ(r.render(&foveart_engine_trace_rays, s.tracer.get(), s.view, gaze, 0, executor).status,
            FOVEART_RESULT_SUCCESS);
  EXPECT_EQ(r.image().rgb, full_render(s, 2, 7, executor).rgb) << "a reset history is the frame alone";
  const foveation::ImageRgb first = r.image();
  ASSERT_EQ(r.render(&foveart_engine_trace_rays, s.tracer.get(), s.view, gaze, 1, executor).status,
            FOVEART_RESULT_SUCCESS);
  EXPECT_NE(r.image().rgb, first.rgb);
  EXPECT_FALSE(r.accumulator().last_was_reset()) << "a still view and gaze keep the history";
  // The weight of a foveated view's history at 2 rays per point (temporal_options_for_rays), not a frame's alpha.
  EXPECT_FLOAT_EQ(r.accumulator().frame_weight(), 1.0f - std::pow(1.0f - vs.temporal_options.current_weight, 2.0f));
  EXPECT_THROW(eval::FullTaaRender(eval::taa_view_settings("off", 1, 7, foveation::PixelFilter::box, false)),
               std::invalid_argument);
}

TEST(PricelistFullTaa, ErrorFallsAsFramesAccumulateAtAStillView) {
  SmallScene s(32, 36);
  foveation::Executor executor(2);
  const foveation::ImageRgb reference = full_render(s, 512, 1000, executor);
  eval::FullTaaRender r(eval::taa_view_settings("reproject", 1, 1, foveation::PixelFilter::box, false));
  std::vector<double> psnr;  // after 1, 4 and 16 frames
  for (std::uint64_t i = 0; i < 16; ++i) {
    ASSERT_EQ(r.render(&foveart_engine_trace_rays, s.tracer.get(), s.view, glm::vec2(16, 18), i, executor).status,
              FOVEART_RESULT_SUCCESS);
    if (i == 0 || i == 3 || i == 15) psnr.push_back(display_psnr(r.image(), reference));
  }
  EXPECT_GT(psnr[1], psnr[0]);
  EXPECT_GT(psnr[2], psnr[1]);
  EXPECT_GT(psnr[2], psnr[0] + 3.0) << "16 frames of new jitter hold several times the rays of one: " << psnr[0]
                                    << " dB after 1, " << psnr[2] << " after 16";
}
