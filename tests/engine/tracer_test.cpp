// The Embree tracer: hits against known geometry, effect detection and the
// per-effect ray counters, kernel specialisation, the C callback contract and
// thread independence of the rendered image.
#include <engine/default_scene.hpp>
#include <engine/render.hpp>
#include <foveation/ray_batch.hpp>
#include <engine/tracer.hpp>

#include <foveation/eye_rays.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <limits>

#include "../foveation/test_executor.hpp"

using namespace foveart::engine;

namespace {

using foveart::foveation::test::executor;

// A square [-s,s]^2 in the plane y = h facing +y (s = 0.5 gives a unit quad).
void add_floor(Scene& scene, float s, float h, uint32_t material) {
  const uint32_t b = static_cast<uint32_t>(scene.mesh.positions.size());
  for (glm::vec3 p : {glm::vec3(-s, h, s), glm::vec3(s, h, s), glm::vec3(s, h, -s), glm::vec3(-s, h, -s)}) {
    scene.mesh.positions.push_back(p);
    scene.mesh.normals.push_back(glm::vec3(0, 1, 0));
  }
  for (glm::vec2 uv : {glm::vec2(0, 1), glm::vec2(1, 1), glm::vec2(1, 0), glm::vec2(0, 0)}) scene.mesh.uv0.push_back(uv);
  scene.mesh.triangles.emplace_back(b, b + 1, b + 2);
  scene.mesh.triangles.emplace_back(b, b + 2, b + 3);
  scene.mesh.triangle_material.push_back(material);
  scene.mesh.triangle_material.push_back(material);
}

Material rough() {
  Material m;
  m.metallic = 0.0f;
  m.roughness = 1.0f;
  return m;
}

Texture red_green_texture() {
  Texture t;
  t.width = 2;
  t.height = 1;
  t.texels = {glm::vec4(1, 0, 0, 1), glm::vec4(0, 1, 0, 1)};
  t.nearest = true;
  return t;
}

struct SceneSpec {
  bool light = false, mirror = false, glass = false, texture = false;
};

// A floor plus a second floor above it (so shadow rays can be blocked).
Scene effect_scene(const SceneSpec& spec) {
  Scene s;
  s.source = "test";
  Material floor = rough();
  if (spec.mirror) floor.roughness = 0.0f;
  if (spec.texture) {
    s.textures.push_back(red_green_texture());
    floor.base_color_texture = 0;
  }
  s.materials.push_back(floor);
  Material top = rough();
  if (spec.glass) {
    top.transmission = 1.0f;
    top.roughness = 0.6f;  // not mirror-like: refraction only
  }
  s.materials.push_back(top);
  add_floor(s, 10.0f, 0.0f, 0);
  add_floor(s, 1.0f, 1.0f, 1);
  if (spec.light) {
    Light l;
    l.position = glm::vec3(3.0f, 4.0f, 0.0f);
    l.intensity = 20.0f;
    s.lights.push_back(l);
  }
  return s;
}

// A batch of ray_count explicit rays (origins, directions: xyz each) writing to rgb.
FoveartRayBatch explicit_batch(const float* origins_m, const float* directions, float* rgb, uint32_t ray_count) {
  FoveartRayBatch b{};
  b.type = FOVEART_TYPE_RAY_BATCH;
  b.size = sizeof(b);
  b.ray_count = ray_count;
  b.origins_m = origins_m;
  b.directions = directions;
  b.out_rgb = rgb;
  return b;
}

// Rays from above looking down at the floor, over a 16 x 16 grid.
std::vector<glm::vec3> trace_down(Tracer& tracer) {
  std::vector<float> o, d, rgb(3 * 256);
  for (int i = 0; i < 256; ++i) {
    const float x = -3.0f + 6.0f * static_cast<float>(i % 16) / 15.0f;
    const float z = -3.0f + 6.0f * static_cast<float>(i / 16) / 15.0f;
    o.insert(o.end(), {x, 3.0f, z});
    const glm::vec3 dir = glm::normalize(glm::vec3(0.2f, -1.0f, 0.1f));
    d.insert(d.end(), {dir.x, dir.y, dir.z});
  }
  FoveartRayBatch b = explicit_batch(o.data(), d.data(), rgb.data(), 256);
  EXPECT_EQ(foveart_engine_trace_rays(&tracer, &b), FOVEART_RESULT_SUCCESS);
  std::vector<glm::vec3> out;
  for (int i = 0; i < 256; ++i) out.emplace_back(rgb[3 * i], rgb[3 * i + 1], rgb[3 * i + 2]);
  return out;
}

std::unique_ptr<Tracer> make(Scene s, TracerOptions o = {}) {
  o.embree_config = "threads=1";
  std::string error;
  auto t = Tracer::create(std::move(s), o, &error);
  EXPECT_TRUE(t) << error;
  return t;
}

FoveartEyeView small_view(const Scene& scene, uint32_t w, uint32_t h) {
  FoveartEyeView v = fove_eye_view(0, scene_head(scene));
  v.width_px = w;
  v.height_px = h;
  return v;
}

}  // namespace

TEST(Tracer, RayHitsUnitQuadAtKnownDistanceNormalAndUv) {
  Scene s;
  s.materials.push_back(rough());
  add_floor(s, 0.5f, 0.0f, 0);  // [-0.5,0.5]^2 at y = 0, uv (0,0) at (-0.5, *, -0.5)
  auto t = make(std::move(s));
  const HitRecord h = t->intersect({0.25f, 2.0f, 0.1f}, {0.0f, -1.0f, 0.0f});
  ASSERT_TRUE(h.hit);
  EXPECT_NEAR(h.t, 2.0f, 1e-5f);
  EXPECT_NEAR(h.normal.x, 0.0f, 1e-6f);
  EXPECT_NEAR(h.normal.y, 1.0f, 1e-6f);
  EXPECT_NEAR(h.uv.x, 0.75f, 1e-5f);  // u = x + 0.5
  EXPECT_NEAR(h.uv.y, 0.6f, 1e-5f);   // v = z + 0.5
  EXPECT_FALSE(t->intersect({0.75f, 2.0f, 0.0f}, {0.0f, -1.0f, 0.0f}).hit);
  EXPECT_FALSE(t->intersect({0.0f, 2.0f, 0.0f}, {0.0f, 1.0f, 0.0f}).hit);
}

// The depth per ray (ray_trace.h, TAA reprojection): the hit distance, +inf
// for the sky; a batch of the older, smaller size gets nothing written there.
TEST(Tracer, BatchDepthIsTheHitDistanceAndInfinityForTheSky) {
  Scene s;
  s.materials.push_back(rough());
  add_floor(s, 0.5f, 0.0f, 0);
  auto t = make(std::move(s));
  const float o[6] = {0.25f, 2.0f, 0.1f, 0.25f, 2.0f, 0.1f};
  const float d[6] = {0.0f, -1.0f, 0.0f, 0.0f, 1.0f, 0.0f};  // down onto the quad, up into the sky
  float rgb[6] = {}, depth[2] = {-1.0f, -1.0f};
  FoveartRayBatch b = explicit_batch(o, d, rgb, 2);
  b.out_depth_m = depth;
  ASSERT_EQ(foveart_engine_trace_rays(t.get(), &b), FOVEART_RESULT_SUCCESS);
  EXPECT_NEAR(depth[0], 2.0f, 1e-5f);
  EXPECT_TRUE(std::isinf(depth[1]) && depth[1] > 0.0f);
  depth[0] = depth[1] = -1.0f;
  b.size = FOVEART_RAY_BATCH_SIZE_WITH_DEPTH - 1;  // a producer built against the header before depth
  ASSERT_EQ(foveart_engine_trace_rays(t.get(), &b), FOVEART_RESULT_SUCCESS);
  EXPECT_EQ(depth[0], -1.0f);
  EXPECT_EQ(depth[1], -1.0f);
}

class EffectCounters : public ::testing::TestWithParam<int> {};

TEST_P(EffectCounters, PresentEffectsTraceRaysAndAbsentOnesNone) {
  const int bits = GetParam();
  const SceneSpec spec{(bits & 1) != 0, (bits & 2) != 0, (bits & 4) != 0, (bits & 8) != 0};
  auto t = make(effect_scene(spec));
  const Effects fx = t->effects();
  EXPECT_EQ(fx.shadows, spec.light);
  EXPECT_EQ(fx.reflection, spec.mirror);
  EXPECT_EQ(fx.refraction, spec.glass);
  EXPECT_EQ(fx.textures, spec.texture);
  trace_down(*t);
  const RayCounts c = t->counts();
  EXPECT_EQ(c.primary, 256u);
  EXPECT_EQ(c.shadow > 0, spec.light) << c.shadow;
  EXPECT_EQ(c.reflection > 0, spec.mirror) << c.reflection;
  EXPECT_EQ(c.refraction > 0, spec.glass) << c.refraction;
  t->reset_counts();
  EXPECT_EQ(t->counts().total(), 0u);
}

INSTANTIATE_TEST_SUITE_P(AllCombinations, EffectCounters, ::testing::Range(0, 16));

TEST(Tracer, TextureIsSampledOnlyWhenTheSceneHasOne) {
  auto textured = make(effect_scene({false, false, false, true}));
  auto plain = make(effect_scene({}));
  const HitRecord h = textured->intersect({-5.0f, 1.0f, 0.0f}, {0, -1, 0});  // u = 0.25: red texel
  ASSERT_TRUE(h.hit);
  float o[3] = {-5.0f, 1.0f, 0.0f}, d[3] = {0.0f, -1.0f, 0.0f}, rgb_tex[3] = {}, rgb_plain[3] = {};
  FoveartRayBatch b = explicit_batch(o, d, rgb_tex, 1);
  ASSERT_EQ(textured->trace(&b), FOVEART_RESULT_SUCCESS);
  b.out_rgb = rgb_plain;
  ASSERT_EQ(plain->trace(&b), FOVEART_RESULT_SUCCESS);
  EXPECT_GT(rgb_tex[0], 0.0f);
  EXPECT_EQ(rgb_tex[1], 0.0f);  // red texel
  EXPECT_GT(rgb_plain[1], 0.0f);  // white base colour
}

TEST(Tracer, SpecialisedKernelMatchesGenericKernel) {
  for (int bits : {0, 1, 2, 4, 8, 15}) {
    const SceneSpec spec{(bits & 1) != 0, (bits & 2) != 0, (bits & 4) != 0, (bits & 8) != 0};
    TracerOptions generic;
    generic.generic_kernel = true;
    auto a = make(effect_scene(spec));
    auto b = make(effect_scene(spec), generic);
    const auto ia = trace_down(*a);
    const auto ib = trace_down(*b);
    for (size_t i = 0; i < ia.size(); ++i) {
      EXPECT_NEAR(ia[i].x, ib[i].x, 1e-6f) << "bits " << bits << " ray " << i;
      EXPECT_NEAR(ia[i].y, ib[i].y, 1e-6f);
    }
  }
}

TEST(Tracer, AllowedMaskRemovesEffectsFromTheKernel) {
  TracerOptions primary_only;
  primary_only.allowed = Effects::none();
  auto t = make(make_default_scene(), primary_only);
  EXPECT_EQ(t->scene_effects(), Effects::all());
  EXPECT_EQ(t->effects(), Effects::none());
  foveart::foveation::ImageRgb img;
  RenderSettings rs;
  ASSERT_EQ(render_full(&foveart_engine_trace_rays, t.get(), small_view(t->scene(), 32, 36), rs, &img, executor()).status,
            FOVEART_RESULT_SUCCESS);
  EXPECT_EQ(t->counts().primary, 32u * 36u);
  EXPECT_EQ(t->counts().shadow + t->counts().reflection + t->counts().refraction, 0u);
}

TEST(Effects, EveryCombinationReadsBackFromItsNameAndBadNamesAreNamed) {
  for (uint32_t bits = 0; bits < 16; ++bits) {
    const Effects e = Effects::from_bits(bits);
    std::string error;
    const std::optional<Effects> back = parse_effects(to_string(e), &error);
    ASSERT_TRUE(back) << to_string(e) << ": " << error;
    EXPECT_EQ(*back, e) << to_string(e);
  }
  std::string error;
  const std::optional<Effects> listed = parse_effects("refraction,reflection", &error);
  ASSERT_TRUE(listed) << error;
  EXPECT_EQ(*listed, (Effects{false, true, true, false}));
  EXPECT_FALSE(parse_effects("reflection,glitter", &error));
  EXPECT_NE(error.find("'glitter'"), std::string::npos) << error;
  for (const char* empty : {"", "reflection,", ",shadows", "shadows,,textures"}) {
    error.clear();
    EXPECT_FALSE(parse_effects(empty, &error)) << "'" << empty << "'";
    EXPECT_FALSE(error.empty()) << "'" << empty << "'";
  }
}

TEST(DefaultScene, HasTheHardCaseAndEveryEffect) {
  const Scene s = make_default_scene();
  const Effects fx = derive_effects(s);
  EXPECT_EQ(fx, Effects::all());
  EXPECT_GE(s.lights.size(), 2u);
  bool dark = false, bright_emitter = false;
  for (const Material& m : s.materials) {
    dark = dark || (m.base_color.r < 0.05f && m.emissive == glm::vec3(0.0f));
    bright_emitter = bright_emitter || m.emissive.r > 5.0f;
  }
  EXPECT_TRUE(dark);
  EXPECT_TRUE(bright_emitter);
  auto t = make(make_default_scene());
  foveart::foveation::ImageRgb img;
  RenderSettings rs;
  ASSERT_EQ(render_full(&foveart_engine_trace_rays, t.get(), small_view(t->scene(), 48, 54), rs, &img, executor()).status,
            FOVEART_RESULT_SUCCESS);
  const RayCounts c = t->counts();
  EXPECT_GT(c.shadow, 0u);
  EXPECT_GT(c.reflection, 0u);
  EXPECT_GT(c.refraction, 0u);
  float lo = 1e9f, hi = 0.0f;  // high contrast: dark pillars and bright lights in one image
  for (std::size_t i = 1; i < img.rgb.size(); i += 3) {  // green
    lo = std::min(lo, img.rgb[i]);
    hi = std::max(hi, img.rgb[i]);
  }
  EXPECT_LT(lo, 0.05f);
  EXPECT_GT(hi, 1.0f);
}

TEST(Tracer, ManyThreadsGiveTheSameImageAsOne) {
  auto t = make(make_default_scene());
  const FoveartEyeView v = small_view(t->scene(), 64, 72);
  RenderSettings rs;
  rs.spp = 2;
  rs.batch_rays = 96;
  foveart::foveation::Executor one(1), many(4);
  foveart::foveation::ImageRgb a, b;
  ASSERT_EQ(render_full(&foveart_engine_trace_rays, t.get(), v, rs, &a, one).status, FOVEART_RESULT_SUCCESS);
  ASSERT_EQ(render_full(&foveart_engine_trace_rays, t.get(), v, rs, &b, many).status, FOVEART_RESULT_SUCCESS);
  ASSERT_EQ(a.rgb.size(), b.rgb.size());
  for (size_t i = 0; i < a.rgb.size(); ++i) ASSERT_EQ(a.rgb[i], b.rgb[i]) << "pixel " << i;
}

// Without AVX-512, Embree runs 16-wide packets through its ray-stream filter,
// which ignores the valid mask and traces every lane whose tnear <= tfar
// (tracer.cpp, set_inactive_lane). "isa=sse4.2" takes that path on any CPU.
// The default scene has every effect, so its shadow, reflection and
// refraction packets are partly filled: they render without tripping Embree's
// ray checks, and each pixel as the native kernels render it. Kernels of
// another width may round a hit distance differently, which moves a shadow
// or refraction at an edge: a few pixels may differ, not the image.
TEST(Tracer, PartlyFilledPacketsOnEmbreesStreamPathRenderAsNatively) {
  TracerOptions native, stream;
  native.embree_config = "threads=1";
  stream.embree_config = "threads=1,isa=sse4.2";
  std::string error;
  auto a = Tracer::create(make_default_scene(), native, &error);
  ASSERT_TRUE(a) << error;
  auto b = Tracer::create(make_default_scene(), stream, &error);
  ASSERT_TRUE(b) << error;
  const FoveartEyeView v = small_view(a->scene(), 64, 72);
  RenderSettings rs;
  foveart::foveation::ImageRgb ia, ib;
  ASSERT_EQ(render_full(&foveart_engine_trace_rays, a.get(), v, rs, &ia, executor()).status, FOVEART_RESULT_SUCCESS);
  ASSERT_EQ(render_full(&foveart_engine_trace_rays, b.get(), v, rs, &ib, executor()).status, FOVEART_RESULT_SUCCESS);
  // Shadow rays follow the hits, so they agree as the pixels do.
  EXPECT_NEAR(double(b->counts().shadow), double(a->counts().shadow), 0.01 * double(a->counts().shadow));
  EXPECT_GT(b->counts().shadow, 0u);
  EXPECT_GT(b->counts().reflection + b->counts().refraction, 0u);
  ASSERT_EQ(ia.rgb.size(), ib.rgb.size());
  std::size_t differing = 0;
  for (std::size_t p = 0; p < ia.pixel_count(); ++p) {
    bool same = true;
    for (int c = 0; c < 3; ++c) same = same && std::abs(ia.rgb[3 * p + c] - ib.rgb[3 * p + c]) <= 1e-4f;
    differing += same ? 0 : 1;
  }
  EXPECT_LE(differing, ia.pixel_count() / 100) << differing << " of " << ia.pixel_count() << " pixels differ";
}

// The full frame is traced tile by tile; the tile shape follows the batch size
// and changes which rays share a packet, never a pixel's colour.
TEST(Tracer, FullRenderTilesCoverTheImageAndDoNotChangeIt) {
  auto t = make(make_default_scene());
  const FoveartEyeView v = small_view(t->scene(), 100, 72);
  RenderSettings big;
  RenderSettings tiny = big;
  tiny.batch_rays = 40;
  foveart::foveation::ImageRgb a, b;
  const RenderResult ra = render_full(&foveart_engine_trace_rays, t.get(), v, big, &a, executor());
  const RenderResult rb = render_full(&foveart_engine_trace_rays, t.get(), v, tiny, &b, executor());
  ASSERT_EQ(ra.status, FOVEART_RESULT_SUCCESS);
  ASSERT_EQ(rb.status, FOVEART_RESULT_SUCCESS);
  EXPECT_EQ(ra.tile_width_px, 64u);  // 4096 rays: 64 x 64 tiles
  EXPECT_EQ(ra.tile_height_px, 64u);
  EXPECT_EQ(ra.tiles_x, 2u);
  EXPECT_EQ(ra.tile_ms.size(), 4u);
  EXPECT_EQ(rb.tile_width_px, 40u);  // 40 rays: 40 x 1
  EXPECT_EQ(rb.tile_height_px, 1u);
  EXPECT_EQ(rb.tiles_x, 3u);
  EXPECT_EQ(rb.tile_ms.size(), 3u * 72u);
  for (double ms : rb.tile_ms) EXPECT_GT(ms, 0.0);
  ASSERT_EQ(a.rgb.size(), b.rgb.size());
  for (size_t i = 0; i < a.rgb.size(); ++i) ASSERT_EQ(a.rgb[i], b.rgb[i]) << "pixel " << i;
}

// Without jitter every ray goes through its pixel's centre (any seed), and the
// depth per pixel is that ray's hit distance: the price list's motion tracking.
TEST(Tracer, FullRenderThroughPixelCentresReturnsTheirDepth) {
  auto t = make(make_default_scene());
  const FoveartEyeView v = small_view(t->scene(), 48, 40);
  RenderSettings centres;
  centres.jitter = false;
  std::vector<float> depth_a, depth_b;
  centres.out_depth_m = &depth_a;
  foveart::foveation::ImageRgb a, b;
  ASSERT_EQ(render_full(&foveart_engine_trace_rays, t.get(), v, centres, &a, executor()).status,
            FOVEART_RESULT_SUCCESS);
  centres.seed = 99;
  centres.out_depth_m = &depth_b;
  ASSERT_EQ(render_full(&foveart_engine_trace_rays, t.get(), v, centres, &b, executor()).status,
            FOVEART_RESULT_SUCCESS);
  EXPECT_EQ(a.rgb, b.rgb) << "the seed moves jittered rays only";
  EXPECT_EQ(depth_a, depth_b);
  ASSERT_EQ(depth_a.size(), std::size_t(48 * 40));
  // Each pixel's depth is the hit distance of the ray through its centre.
  const foveart::foveation::EyeFrustum f = foveart::foveation::eye_frustum(v);
  const foveart::foveation::EyePose pose = foveart::foveation::eye_pose(v);
  int hits = 0;
  for (int y = 0; y < 40; y += 7) {
    for (int x = 0; x < 48; x += 5) {
      const glm::vec3 d = foveart::foveation::eye_ray_direction(f, pose, {float(x) + 0.5f, float(y) + 0.5f});
      const HitRecord h = t->intersect(pose.position_m, d);
      const float depth = depth_a[std::size_t(y) * 48 + std::size_t(x)];
      if (h.hit) {
        EXPECT_NEAR(depth, h.t, 1e-4f * h.t) << x << "," << y;
        ++hits;
      } else {
        EXPECT_TRUE(std::isinf(depth)) << x << "," << y;
      }
    }
  }
  EXPECT_GT(hits, 0);
}

TEST(Tracer, RaysFromViewAndSamplePositionsEqualExplicitRays) {
  auto t = make(make_default_scene());
  const FoveartEyeView v = small_view(t->scene(), 64, 72);
  std::vector<glm::vec2> px;
  for (int i = 0; i < 100; ++i) px.emplace_back(0.64f * static_cast<float>(i), 0.72f * static_cast<float>(i) + 0.3f);
  // Explicit rays from the one batch builder (foveation::RayBatch)...
  foveart::foveation::RayBatch explicit_rays;
  explicit_rays.resize(px.size());
  for (size_t i = 0; i < px.size(); ++i)
    explicit_rays.set_sample(i, px[i], static_cast<uint32_t>(i));
  ASSERT_EQ(explicit_rays.trace(&foveart_engine_trace_rays, t.get(), v, 0, static_cast<uint32_t>(px.size())),
            FOVEART_RESULT_SUCCESS);
  // ... and the engine's own rays from the view and the sample positions alone.
  std::vector<float> sample_px, rgb(3 * px.size(), 0.0f);
  for (glm::vec2 p : px) sample_px.insert(sample_px.end(), {p.x, p.y});
  FoveartRayBatch b{};
  b.type = FOVEART_TYPE_RAY_BATCH;
  b.size = sizeof(b);
  b.view = &v;
  b.ray_count = static_cast<uint32_t>(px.size());
  b.sample_px = sample_px.data();
  b.out_rgb = rgb.data();
  ASSERT_EQ(t->trace(&b), FOVEART_RESULT_SUCCESS);
  for (size_t i = 0; i < px.size(); ++i) EXPECT_NEAR(rgb[3 * i + 1], explicit_rays.rgb(i).y, 1e-4f) << i;
}

TEST(Tracer, BadBatchesAreRejectedAndBadRaysAreBlack) {
  auto t = make(effect_scene({true, false, false, false}));
  float o[6] = {0, 3, 0, 0, 3, 0};
  float d[6] = {0, -1, 0, std::numeric_limits<float>::quiet_NaN(), 0, 0};
  float rgb[6] = {-1, -1, -1, -1, -1, -1};
  FoveartRayBatch b = explicit_batch(o, d, rgb, 2);
  EXPECT_EQ(foveart_engine_trace_rays(nullptr, &b), FOVEART_RESULT_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(foveart_engine_trace_rays(t.get(), nullptr), FOVEART_RESULT_ERROR_INVALID_ARGUMENT);
  FoveartRayBatch wrong = b;
  wrong.type = FOVEART_TYPE_EYE_VIEW;
  EXPECT_EQ(t->trace(&wrong), FOVEART_RESULT_ERROR_INVALID_ARGUMENT);
  wrong = b;
  wrong.size = 8;
  EXPECT_EQ(t->trace(&wrong), FOVEART_RESULT_ERROR_INVALID_ARGUMENT);
  wrong = b;
  wrong.out_rgb = nullptr;
  EXPECT_EQ(t->trace(&wrong), FOVEART_RESULT_ERROR_INVALID_ARGUMENT);
  wrong = b;
  wrong.directions = nullptr;  // and no view to fall back on
  EXPECT_EQ(t->trace(&wrong), FOVEART_RESULT_ERROR_INVALID_ARGUMENT);
  ASSERT_EQ(t->trace(&b), FOVEART_RESULT_SUCCESS);
  EXPECT_GT(rgb[1], 0.0f);  // the good ray sees the lit floor
  EXPECT_EQ(rgb[3], 0.0f);  // the NaN ray is black, not NaN
  EXPECT_EQ(rgb[4], 0.0f);
}

// engine::prepare_scene, which both engines run: each broken scene is refused, naming its source
// and what is wrong. A vertex beyond 1e9 m would spawn secondary rays that Embree aborts on.
TEST(Tracer, ABrokenOrFarSceneIsRefusedByName) {
  struct Case {
    void (*spoil)(Scene&);
    const char* says;
  };
  const Case cases[] = {
      {[](Scene& s) { s.mesh.positions[2].z = 2e9f; },
       "far: vertex 2 at (0.5, 0, 2e+09) m is not finite or lies beyond"},
      {[](Scene& s) { s.mesh.positions[0].x = std::numeric_limits<float>::quiet_NaN(); }, "far: vertex 0 at (nan"},
      {[](Scene& s) { s.mesh.normals.pop_back(); }, "far: inconsistent mesh arrays"},
      {[](Scene& s) { s.mesh.triangles[1].z = 99; }, "far: triangle 1 refers past the vertex or material arrays"},
      {[](Scene& s) { s.textures.push_back(Texture{}); }, "far: texture 0 has no or the wrong number of texels"},
  };
  for (const Case& c : cases) {
    Scene scene;
    scene.source = "far";
    scene.materials.push_back(rough());
    add_floor(scene, 0.5f, 0.0f, 0);
    c.spoil(scene);
    std::string error;
    EXPECT_EQ(Tracer::create(std::move(scene), {}, &error), nullptr) << c.says;
    EXPECT_EQ(error.rfind(c.says, 0), 0u) << error;
  }
}

TEST(Tracer, EmptySceneSeesOnlySky) {
  Scene s;
  s.source = "empty";
  auto t = make(std::move(s));
  EXPECT_FALSE(t->intersect({0, 0, 0}, {0, 0, -1}).hit);
  float o[3] = {0, 0, 0}, d[3] = {0, 1, 0}, rgb[3] = {};
  FoveartRayBatch b = explicit_batch(o, d, rgb, 1);
  ASSERT_EQ(t->trace(&b), FOVEART_RESULT_SUCCESS);
  EXPECT_NEAR(rgb[2], Scene{}.sky_zenith.z, 1e-6f);
}

TEST(Tracer, AlphaMaskCutsOutTexelsBelowTheCutoff) {
  Scene s;
  Material m = rough();
  m.alpha_mode = AlphaMode::kMask;
  m.alpha_cutoff = 0.5f;
  m.base_color_texture = 0;
  s.materials.push_back(m);
  Texture t;  // left half transparent, right half opaque
  t.width = 2;
  t.height = 1;
  t.texels = {glm::vec4(1, 1, 1, 0), glm::vec4(1, 1, 1, 1)};
  t.nearest = true;
  s.textures.push_back(t);
  add_floor(s, 1.0f, 0.0f, 0);
  auto tr = make(std::move(s));
  EXPECT_FALSE(tr->intersect({-0.5f, 1.0f, 0.0f}, {0, -1, 0}).hit);  // u = 0.25: alpha 0
  EXPECT_TRUE(tr->intersect({0.5f, 1.0f, 0.0f}, {0, -1, 0}).hit);    // u = 0.75: alpha 1
}
