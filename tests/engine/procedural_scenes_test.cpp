// The procedural benchmark interiors, the standing viewer, and automatic
// exposure: a room lit in photometric units shows with a visible range.
#include <engine/effects.hpp>
#include <engine/exposure.hpp>
#include <engine/gltf_loader.hpp>
#include <engine/procedural_scenes.hpp>
#include <engine/render.hpp>
#include <engine/tracer.hpp>

#include <foveation/display_transform.hpp>

#include <glm/gtc/quaternion.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>

#include "../foveation/test_executor.hpp"

using namespace foveart::engine;
namespace fv = foveart::foveation;

namespace {

using foveart::foveation::test::executor;

// The FOVE left eye at a quarter of its size per axis (the same field of view).
FoveartEyeView small_fove_view(const Scene& scene) {
  FoveartEyeView v = fove_eye_view(0, scene_head(scene));
  v.width_px = 320;
  v.height_px = 360;
  return v;
}

TEST(ProceduralScenes, AMistypedNameListsTheBuiltInOnes) {
  const LoadResult r = load_scene("hal");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error.rfind("hal: no such file, and not a built-in scene (default", 0), 0u) << r.error;
  for (const std::string& name : procedural_scene_names()) EXPECT_NE(r.error.find(name), std::string::npos) << r.error;
  EXPECT_NE(load_scene("missing.gltf").error.find("missing.gltf: no such file"), std::string::npos)
      << "a path keeps the loader's own message";
}

TEST(ProceduralScenes, EachLoadsByNameWithACameraInsideAndOnlyTheEffectsItHas) {
  for (const std::string& name : procedural_scene_names()) {
    LoadResult loaded = load_scene(name);
    ASSERT_TRUE(loaded.ok()) << name << ": " << loaded.error;
    const Scene& s = *loaded.scene;
    EXPECT_EQ(s.source, name);
    ASSERT_TRUE(s.camera.has_value()) << name;
    const Bounds b = scene_bounds(s.mesh);
    for (int i = 0; i < 3; ++i) {
      EXPECT_GT(s.camera->position_m[i], b.min[i]) << name << ": the viewer stands inside";
      EXPECT_LT(s.camera->position_m[i], b.max[i]) << name;
    }
    EXPECT_FALSE(s.lights.empty()) << name;
    const Effects e = derive_effects(s);
    EXPECT_TRUE(e.shadows) << name;
    EXPECT_FALSE(e.reflection || e.refraction) << name << ": no mirror or glass in these rooms";
    EXPECT_EQ(e.textures, name == "hall") << name;
  }
  EXPECT_GT(make_dense_room().mesh.triangles.size(), 300000u);
  EXPECT_FALSE(make_procedural_scene("nonsense").has_value());
}

TEST(AutoExposure, OnlyDarkensAndMapsTheBrightTenthToTheRollOff) {
  fv::ImageRgb dim(10, 10);
  for (float& c : dim.rgb) c = 0.1f;
  EXPECT_EQ(exposure_for(dim), 1.0f);  // already in display range: shown as made
  fv::ImageRgb bright(10, 10);
  for (std::size_t i = 0; i < bright.pixel_count(); ++i)
    for (int c = 0; c < 3; ++c) bright.rgb[i * 3 + std::size_t(c)] = i < 95 ? 10.0f : 1000.0f;
  // The 90th percentile is 10: it maps to 0.76; the brightest 5 % may roll off.
  EXPECT_FLOAT_EQ(exposure_for(bright), AutoExposure::kTargetLuminance / 10.0f);
  EXPECT_EQ(exposure_for(fv::ImageRgb(4, 4)), 1.0f);  // black: nothing to meter
}

// Twelve 108 cd point lights in real units burn the room out without exposure;
// auto exposure and the default curve leave at most 5 % of it pure white.
TEST(AutoExposure, PhotometricRoomShowsWithAVisibleRange) {
  std::string error;
  auto tracer = Tracer::create(make_lit_room(), {}, &error);
  ASSERT_NE(tracer, nullptr) << error;
  const FoveartEyeView view = small_fove_view(tracer->scene());
  RenderSettings rs;
  fv::ImageRgb image;
  ASSERT_EQ(render_full(&foveart_engine_trace_rays, tracer.get(), view, rs, &image, executor()).status,
            FOVEART_RESULT_SUCCESS);
  const std::optional<AutoExposure> a = auto_exposure(&foveart_engine_trace_rays, tracer.get(), view, executor(), &error);
  ASSERT_TRUE(a.has_value()) << error;
  EXPECT_EQ(a->prepass_width_px, 40);
  EXPECT_EQ(a->prepass_height_px, 45);
  EXPECT_LT(a->exposure, 0.5f);
  const double burnt = fv::white_clipped_fraction(image, fv::kClampOnly);
  const double shown = fv::white_clipped_fraction(image, {a->exposure, fv::ToneMap::pbr_neutral});
  EXPECT_GT(burnt, 0.5) << "the room in real units is not bright enough to test exposure";
  EXPECT_LE(shown, 0.05);
  // And the image keeps its range: not everything pushed into the dark.
  double mean_luminance = 0.0;
  for (std::size_t i = 0; i < image.pixel_count(); ++i) {
    const glm::vec3 d = fv::DisplayTransform{a->exposure, fv::ToneMap::pbr_neutral}.apply(
        glm::vec3(image.rgb[i * 3], image.rgb[i * 3 + 1], image.rgb[i * 3 + 2]));
    mean_luminance += double(0.2126f * d.r + 0.7152f * d.g + 0.0722f * d.b);
  }
  mean_luminance /= double(image.pixel_count());
  EXPECT_GT(mean_luminance, 0.15);
  EXPECT_LT(mean_luminance, 0.7);
}

TEST(StandingViewer, LooksAtThePointUprightFromWhereItStands) {
  Camera base;
  base.position_m = {0.0f, 1.6f, 0.0f};
  for (glm::vec3 target : {glm::vec3(5.0f, 1.6f, 0.0f), glm::vec3(-2.0f, 0.5f, -3.0f), glm::vec3(0.0f, 3.0f, 4.0f)}) {
    const Camera c = standing_viewer(base, glm::vec3(0.0f, 1.6f, 0.0f), target);
    const glm::vec3 forward = c.orientation * glm::vec3(0.0f, 0.0f, -1.0f);
    const glm::vec3 want = glm::normalize(target - c.position_m);
    EXPECT_NEAR(glm::dot(forward, want), 1.0f, 1e-5f) << target.x << "," << target.y << "," << target.z;
    const glm::vec3 right = c.orientation * glm::vec3(1.0f, 0.0f, 0.0f);
    EXPECT_NEAR(right.y, 0.0f, 1e-5f) << "no roll";
  }
  // Position only: the orientation stays the base camera's.
  base.orientation = glm::angleAxis(0.3f, glm::vec3(0.0f, 1.0f, 0.0f));
  const Camera moved = standing_viewer(base, glm::vec3(1.0f, 2.0f, 3.0f), std::nullopt);
  EXPECT_EQ(moved.position_m, glm::vec3(1.0f, 2.0f, 3.0f));
  EXPECT_EQ(moved.orientation, base.orientation);
  // A point where the viewer stands leaves the orientation alone.
  EXPECT_EQ(standing_viewer(base, std::nullopt, base.position_m).orientation, base.orientation);
}

}  // namespace
