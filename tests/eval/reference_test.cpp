// The converged reference (eval/reference.hpp): its cache round trip,
// corruption rejected and rendered again, the residual estimate; PFM files;
// the reference cache key of every pixel filter.
#include "gltf_fixtures.hpp"

#include "small_scene.hpp"
#include <eval/pfm.hpp>
#include <eval/reference.hpp>

#include <engine/gltf_loader.hpp>
#include <engine/render.hpp>
#include <engine/tracer.hpp>
#include <foveation/executor.hpp>
#include <metrics/image_metrics.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <sstream>

namespace fs = std::filesystem;
using namespace foveart;

namespace {

using eval_test::SmallScene;

}  // namespace

TEST(Reference, CacheRoundTripAndCorruptionIsRejectedAndRenderedAgain) {
  engine_test::TempDir dir;
  SmallScene s(32, 36);
  foveation::Executor executor(2);
  eval::ReferenceOptions o;
  o.spp = 8;
  o.cache_dir = dir.path.string();
  std::vector<std::string> log;
  const auto logger = [&](const std::string& m) { log.push_back(m); };
  std::string error;
  const glm::vec2 gaze(16, 18);
  auto first = eval::converged_reference(&foveart_engine_trace_rays, s.tracer.get(), s.hash, s.view, gaze, o, executor, logger, &error);
  ASSERT_TRUE(first) << error;
  EXPECT_FALSE(first->from_cache);
  EXPECT_EQ(first->spp, 8);
  ASSERT_TRUE(fs::exists(first->cache_file));
  auto second = eval::converged_reference(&foveart_engine_trace_rays, s.tracer.get(), s.hash, s.view, gaze, o, executor, logger, &error);
  ASSERT_TRUE(second) << error;
  EXPECT_TRUE(second->from_cache);
  EXPECT_EQ(second->image.rgb, first->image.rgb);
  EXPECT_EQ(second->half_difference2, first->half_difference2);
  EXPECT_EQ(second->half_difference_luma, first->half_difference_luma);
  EXPECT_TRUE(log.empty());
  // The signed luma difference is a convex mix of the channels' differences: never beyond the largest.
  ASSERT_EQ(first->half_difference_luma.size(), first->half_difference2.size());
  bool any_noise = false;
  for (std::size_t i = 0; i < first->half_difference2.size(); ++i) {
    EXPECT_LE(std::abs(first->half_difference_luma[i]), std::sqrt(3.0f * first->half_difference2[i]) + 1e-6f) << i;
    any_noise = any_noise || first->half_difference_luma[i] != 0.0f;
  }
  EXPECT_TRUE(any_noise) << "8 rays per pixel in two halves differ somewhere";

  // One flipped byte in the payload: a clear message naming the file, then a fresh render.
  {
    std::fstream f(first->cache_file, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(100);
    char c = 0;
    f.read(&c, 1);
    f.seekp(100);
    c = char(c ^ 0x40);
    f.write(&c, 1);
  }
  std::string why;
  const std::uint64_t key = eval::reference_key(s.hash, s.view, 8, o.seed, o.pixel_filter);
  EXPECT_FALSE(eval::read_reference(first->cache_file, key, &why));
  EXPECT_NE(why.find("checksum mismatch"), std::string::npos) << why;
  EXPECT_NE(why.find(first->cache_file), std::string::npos) << why;
  auto third = eval::converged_reference(&foveart_engine_trace_rays, s.tracer.get(), s.hash, s.view, gaze, o, executor, logger, &error);
  ASSERT_TRUE(third) << error;
  EXPECT_FALSE(third->from_cache);
  EXPECT_EQ(third->image.rgb, first->image.rgb);  // the same chunks, the same image
  ASSERT_EQ(log.size(), 1u);
  EXPECT_NE(log[0].find("checksum mismatch"), std::string::npos) << log[0];

  // Truncated, another key.
  fs::resize_file(first->cache_file, 50);
  EXPECT_FALSE(eval::read_reference(first->cache_file, key, &why));
  EXPECT_NE(why.find("size"), std::string::npos) << why;
  auto fourth = eval::converged_reference(&foveart_engine_trace_rays, s.tracer.get(), s.hash, s.view, gaze, o, executor, logger, &error);
  ASSERT_TRUE(fourth);
  EXPECT_FALSE(eval::read_reference(first->cache_file, key + 1, &why));
  EXPECT_NE(why.find("key mismatch"), std::string::npos) << why;
}

// The reference is the expectation of the images measured against it, so it
// follows their pixel filter: another filter is another image, another cache
// file, and a box file is never read for a bspline2 reference.
TEST(Reference, PixelFilterIsPartOfTheReferenceAndItsCacheKey) {
  engine_test::TempDir dir;
  SmallScene s(32, 36);
  foveation::Executor executor(2);
  eval::ReferenceOptions o;
  o.spp = 16;
  o.cache_dir = dir.path.string();
  std::string error;
  const glm::vec2 gaze(16, 18);
  auto box = eval::converged_reference(&foveart_engine_trace_rays, s.tracer.get(), s.hash, s.view, gaze, o, executor, {}, &error);
  ASSERT_TRUE(box) << error;
  o.pixel_filter = foveation::PixelFilter::bspline2;
  auto bspline = eval::converged_reference(&foveart_engine_trace_rays, s.tracer.get(), s.hash, s.view, gaze, o, executor, {}, &error);
  ASSERT_TRUE(bspline) << error;
  EXPECT_FALSE(bspline->from_cache);
  EXPECT_NE(bspline->cache_file, box->cache_file);
  EXPECT_NE(eval::reference_key(s.hash, s.view, 16, o.seed, foveation::PixelFilter::box),
            eval::reference_key(s.hash, s.view, 16, o.seed, foveation::PixelFilter::bspline2));
  EXPECT_NE(bspline->image.rgb, box->image.rgb);
  // The reference renders with the filter: its image is the full render's with the same settings.
  foveation::ImageRgb direct;
  double diff2 = 0.0;
  {
    engine::RenderSettings rs;
    rs.spp = 16;
    rs.seed = 12345;
    rs.pixel_filter = foveation::PixelFilter::bspline2;
    ASSERT_EQ(engine::render_full(&foveart_engine_trace_rays, s.tracer.get(), s.view, rs, &direct, executor).status,
              FOVEART_RESULT_SUCCESS);
    for (std::size_t i = 0; i < direct.rgb.size(); ++i) {
      const double d = double(direct.rgb[i]) - double(bspline->image.rgb[i]);
      diff2 += d * d;
    }
  }
  double box_diff2 = 0.0;
  for (std::size_t i = 0; i < direct.rgb.size(); ++i) {
    const double d = double(direct.rgb[i]) - double(box->image.rgb[i]);
    box_diff2 += d * d;
  }
  EXPECT_LT(diff2, box_diff2);  // an independent bspline2 render lies nearer the bspline2 reference
  auto again = eval::converged_reference(&foveart_engine_trace_rays, s.tracer.get(), s.hash, s.view, gaze, o, executor, {}, &error);
  ASSERT_TRUE(again) << error;
  EXPECT_TRUE(again->from_cache);
  EXPECT_EQ(again->image.rgb, bspline->image.rgb);
}

TEST(Reference, ResidualFallsWithRaysPerPixelAndTheCheckStopsAtItsTarget) {
  SmallScene s(40, 45);
  foveation::Executor executor(2);
  const glm::vec2 gaze(20, 22);
  const auto map = metrics::eccentricity_map(s.view, gaze);
  std::string error;
  eval::ReferenceOptions o;
  o.spp = 4;
  auto r4 = eval::converged_reference(&foveart_engine_trace_rays, s.tracer.get(), s.hash, s.view, gaze, o, executor, {}, &error);
  o.spp = 64;
  auto r64 = eval::converged_reference(&foveart_engine_trace_rays, s.tracer.get(), s.hash, s.view, gaze, o, executor, {}, &error);
  ASSERT_TRUE(r4 && r64) << error;
  // 16x the rays: ~1/16 the residual; between 1/4 and 1/64 in the rings that hold many pixels.
  const auto a = r4->residual_mse(map), b = r64->residual_mse(map);
  for (std::size_t r = 0; r < metrics::kRingCount; ++r) {
    if (map.ring_pixels[r] < 200) continue;
    EXPECT_GT(a[r], 0.0) << r;
    EXPECT_LT(b[r], a[r] / 4.0) << r;
    EXPECT_GT(b[r], a[r] / 64.0) << r;
  }
  // Auto: doubles from min_spp while below baseline_spp * 10^(margin/10), up to max_spp.
  o.spp = 0;
  o.min_spp = 16;
  o.max_spp = 64;
  o.baseline_spp = 1000;  // needs 10,000 rays per pixel: stops at max_spp, not converged
  auto autoref = eval::converged_reference(&foveart_engine_trace_rays, s.tracer.get(), s.hash, s.view, gaze, o, executor, {}, &error);
  ASSERT_TRUE(autoref) << error;
  EXPECT_EQ(autoref->tried_spp, (std::vector<int>{16, 32, 64}));
  EXPECT_FALSE(autoref->converged);
  EXPECT_EQ(autoref->image.rgb, r64->image.rgb);  // doubling reuses chunks: the same image as asking for 64
  ASSERT_EQ(autoref->db_per_doubling.size(), metrics::kRingCount);
  // Needs 10 rays per pixel: 16 is enough, but the 1/N law is only seen after one doubling.
  o.baseline_spp = 1;
  autoref = eval::converged_reference(&foveart_engine_trace_rays, s.tracer.get(), s.hash, s.view, gaze, o, executor, {}, &error);
  ASSERT_TRUE(autoref);
  ASSERT_GE(autoref->tried_spp.size(), 2u);
  EXPECT_EQ(autoref->tried_spp[0], 16);
  if (autoref->converged) {
    for (std::size_t r = 0; r < metrics::kRingCount; ++r)
      if (map.ring_pixels[r] > 0 && std::isfinite(autoref->db_per_doubling[r])) {
        EXPECT_GE(autoref->db_per_doubling[r], 2.0) << r;

      }
  }
}

TEST(Reference, SceneHashFollowsContent) {
  engine::LoadResult a = engine::load_scene("default"), b = engine::load_scene("default");
  EXPECT_EQ(eval::scene_content_hash(*a.scene), eval::scene_content_hash(*b.scene));
  b.scene->materials[0].roughness += 0.01f;
  EXPECT_NE(eval::scene_content_hash(*a.scene), eval::scene_content_hash(*b.scene));
}

TEST(Pfm, RoundTripIsBitExactAndBadFilesAreNamed) {
  engine_test::TempDir dir;
  foveation::ImageRgb im(3, 2);
  for (std::size_t i = 0; i < im.rgb.size(); ++i) im.rgb[i] = float(i) * 0.37f - 1.0f;
  const std::string file = (dir.path / "a.pfm").string();
  std::string e;
  ASSERT_TRUE(eval::write_pfm(file, im, &e)) << e;
  foveation::ImageRgb back;
  ASSERT_TRUE(eval::read_pfm(file, &back, &e)) << e;
  EXPECT_EQ(back.width_px, 3);
  EXPECT_EQ(back.rgb, im.rgb);
  fs::resize_file(file, 20);
  EXPECT_FALSE(eval::read_pfm(file, &back, &e));
  EXPECT_NE(e.find("truncated"), std::string::npos) << e;
  EXPECT_NE(e.find(file), std::string::npos) << e;
}

