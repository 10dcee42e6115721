// hello_foveated --mode full|both through the real loader, the layer and the
// simulated FOVE runtime on lavapipe.
//  * --mode full --engine cpu: the captured swapchain image is, byte for byte,
//    engine::render_full of the submitted view (the layer's seed, box jitter)
//    through foveation::encode_rgba8 with the chained exposure and curve,
//    computed here; the layer traced no frame.
//  * --mode full --engine gpu matches --engine cpu per eccentricity ring
//    within gpu_engine_test.cpp's bounds (ring_compare.hpp): the same rays,
//    traced by the GPU engine (within 1e-3 relative per ray of the CPU engine)
//    and averaged in its own order.
//  * --mode both: one process, a full session then a foveated one; the JSON
//    has both, their ray counts, and speedup = the ratio of the printed medians.
//  * bad combinations exit 2 naming the option.
// The setting is gpu_engine_test.cpp's: 320x360 eyes, MSM k 5, density scale 4
// (about 30.8k points per eye of 115.2k pixels: the foveated frame traces fewer
// rays than the full one), 2 rays per point, temporal "off", static head.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "engine/gltf_loader.hpp"
#include "engine/render.hpp"
#include "engine/tracer.hpp"
#include "foveation/display_transform.hpp"
#include "foveation/executor.hpp"
#include "foveation/eye_rays.hpp"
#include "foveation/rgba8.hpp"
#include "hello_foveated_run.hpp"
#include "ring_compare.hpp"

namespace foveart::layer::test {
namespace {

constexpr int kWidth = 320, kHeight = 360;
constexpr int kFrames = 2;
constexpr int kRaysPerPixel = 2;
constexpr uint64_t kLayerSeed = 1;  // the layer's sample seed; no history: every frame's
// The display transform chained by the app, explicit so the test needs no pre-pass of its own.
constexpr float kExposure = 1.5f;
const foveation::DisplayTransform kDisplay{kExposure, foveation::ToneMap::aces};

struct EyeSize {
  int width, height;
};

class HelloFoveatedMode : public HelloFoveatedRun {
 protected:
  void SetUp() override { set_up(kFrames, "auto"); }

  // hello_foveated --json with the common setting; frames captured into <root>/<name>.
  AppRun launch(const std::string& name, std::vector<std::string> extra, EyeSize eye = {kWidth, kHeight},
                int frames = kFrames) {
    std::vector<std::string> args{FOVEART_HELLO_FOVEATED, "--json", "--eye-size", std::to_string(eye.width),
                                  std::to_string(eye.height), "--interpolation", "msm", "--k", "5", "--density-scale",
                                  "4", "--rays-per-point", std::to_string(kRaysPerPixel), "--temporal", "off",
                                  "--gaze-source", "none", "--exposure", "1.5", "--tone-map", "aces"};
    args.insert(args.end(), extra.begin(), extra.end());
    return run(name, args, frames);
  }
};

constexpr const char* kEyes[2] = {"left", "right"};

// A clean --mode full run of `frames` frames: every frame drawn by the app, none by the layer.
void expect_full(const AppRun& r, const char* engine, EyeSize eye = {kWidth, kHeight}, int frames = kFrames) {
  ASSERT_EQ(r.process.exit_code, 0) << r.process.output;
  ASSERT_TRUE(r.stats.is_object()) << r.process.output;
  EXPECT_EQ(r.stats["mode"], "full");
  EXPECT_EQ(r.stats["engine"], engine);
  EXPECT_EQ(r.stats["frames_submitted"], frames);
  EXPECT_EQ(r.stats["frames_rendered"], frames);
  EXPECT_EQ(r.stats["layer_frames_traced"], 0) << "the layer traced a frame the app did not opt in";
  EXPECT_EQ(r.stats["layer_views_fallback"], 0);
  EXPECT_EQ(r.stats["temporal"], "off");
  EXPECT_EQ(r.stats["trace_clock"], std::string(engine) == "gpu" ? "gpu_timestamps" : "cpu_wall_clock");
  for (int e = 0; e < 2; ++e) {
    EXPECT_EQ(r.stats["rays_per_eye"][e].get<uint64_t>(), uint64_t(eye.width) * eye.height * kRaysPerPixel);
  }
}

// The primary rays of a full run: every pixel of both eyes, kRaysPerPixel each, every frame.
constexpr uint64_t full_primary_rays(EyeSize eye, int frames) {
  return uint64_t(eye.width) * uint64_t(eye.height) * kRaysPerPixel * 2 * uint64_t(frames);
}

TEST_F(HelloFoveatedMode, FullCpuIsRenderFullOfTheSubmittedViewEncodedForTheDisplay) {
  const AppRun r = launch("full_cpu", {"--mode", "full", "--engine", "cpu"});
  ASSERT_NO_FATAL_FAILURE(expect_full(r, "cpu"));
  EXPECT_EQ(r.stats["engine_rays"]["cpu"]["primary"].get<uint64_t>(), full_primary_rays({kWidth, kHeight}, kFrames));
  EXPECT_TRUE(r.stats["engine_rays"]["gpu"].is_null());

  auto loaded = engine::load_scene("default");
  ASSERT_TRUE(loaded.ok()) << loaded.error;
  std::string error;
  auto tracer = engine::Tracer::create(std::move(*loaded.scene), {}, &error);
  ASSERT_NE(tracer, nullptr) << error;
  foveation::Executor executor(2);
  for (int e = 0; e < 2; ++e) {
    SCOPED_TRACE(kEyes[e]);
    // The view the app submitted (the scene's space), as the layer would have traced it.
    const auto& v = r.stats["views"][e];
    const auto position = v["position_m"].get<std::vector<float>>();
    const auto orientation = v["orientation_xyzw"].get<std::vector<float>>();
    const auto fov = v["fov_rad"].get<std::vector<float>>();
    foveation::EyePose pose;
    pose.position_m = {position[0], position[1], position[2]};
    pose.orientation = glm::quat(orientation[3], orientation[0], orientation[1], orientation[2]);
    const FoveartEyeView view =
        foveation::make_eye_view(uint32_t(e), kWidth, kHeight, pose, fov[0], fov[1], fov[2], fov[3]);
    engine::RenderSettings settings;
    settings.spp = kRaysPerPixel;
    settings.seed = kLayerSeed;
    foveation::ImageRgb radiance;
    ASSERT_EQ(engine::render_full(&foveart_engine_trace_rays, tracer.get(), view, settings, &radiance, executor).status,
              FOVEART_RESULT_SUCCESS);
    std::vector<uint8_t> rgba(std::size_t(kWidth) * kHeight * 4);
    foveation::encode_rgba8(radiance, true, kDisplay, rgba.data(), executor);

    const Rgb8 shown = load_rgb(frame(r, kFrames - 1, kEyes[e]));
    ASSERT_EQ(shown.width, kWidth);
    ASSERT_EQ(shown.height, kHeight);
    std::size_t differing = 0;
    int lo = 255, hi = 0;
    for (std::size_t p = 0; p < std::size_t(kWidth) * kHeight; ++p) {
      for (int c = 0; c < 3; ++c) {
        differing += shown.rgb[p * 3 + c] != rgba[p * 4 + c];
        lo = std::min<int>(lo, shown.rgb[p * 3 + c]);
        hi = std::max<int>(hi, shown.rgb[p * 3 + c]);
      }
    }
    // The same rays through the same engine and the same encode: exactly equal.
    EXPECT_EQ(differing, 0u);
    EXPECT_GT(hi - lo, 150) << "a traced scene, not the app's grey placeholder";
    // The control: another jitter seed (another sample set) differs, so the match above is no accident.
    settings.seed = kLayerSeed + 1;
    ASSERT_EQ(engine::render_full(&foveart_engine_trace_rays, tracer.get(), view, settings, &radiance, executor).status,
              FOVEART_RESULT_SUCCESS);
    foveation::encode_rgba8(radiance, true, kDisplay, rgba.data(), executor);
    std::size_t differing_control = 0;
    for (std::size_t p = 0; p < std::size_t(kWidth) * kHeight; ++p)
      for (int c = 0; c < 3; ++c) differing_control += shown.rgb[p * 3 + c] != rgba[p * 4 + c];
    EXPECT_GT(differing_control, 1000u) << "another seed matches as well";
  }
}

// Smaller eyes and one frame: lavapipe traces a 320x360 eye's full render at 2 rays
// per pixel in about 5 s on two shared cores.
constexpr EyeSize kGpuEye{128, 144};

TEST_F(HelloFoveatedMode, FullGpuMatchesFullCpuPerEccentricityRing) {
  const AppRun cpu = launch("full_cpu", {"--mode", "full", "--engine", "cpu"}, kGpuEye, 1);
  ASSERT_NO_FATAL_FAILURE(expect_full(cpu, "cpu", kGpuEye, 1));
  const AppRun gpu = launch("full_gpu", {"--mode", "full", "--engine", "gpu"}, kGpuEye, 1);
  ASSERT_NO_FATAL_FAILURE(expect_full(gpu, "gpu", kGpuEye, 1));
  // Who traced: the GPU engine every ray of the full render, the CPU engine none.
  ASSERT_TRUE(gpu.stats["engine_rays"]["gpu"].is_object()) << gpu.process.output;
  EXPECT_EQ(gpu.stats["engine_rays"]["gpu"]["primary"].get<uint64_t>(), full_primary_rays(kGpuEye, 1));
  EXPECT_EQ(gpu.stats["engine_rays"]["cpu"]["primary"].get<uint64_t>(), 0u);
  EXPECT_EQ(gpu.stats["views"], cpu.stats["views"]);
  for (int e = 0; e < 2; ++e) {
    SCOPED_TRACE(kEyes[e]);
    const auto fov = gpu.stats["views"][e]["fov_rad"].get<std::vector<double>>();
    const Rgb8 a = load_rgb(frame(cpu, 0, kEyes[e]));
    const Rgb8 b = load_rgb(frame(gpu, 0, kEyes[e]));
    ASSERT_EQ(a.width, kGpuEye.width);
    ASSERT_EQ(b.width, kGpuEye.width);
    ASSERT_EQ(a.rgb.size(), b.rgb.size());
    // A full render has no gaze: rings around the image centre.
    const auto rings = compare_rings(a, b, fov, kGpuEye.width / 2.0, kGpuEye.height / 2.0);
    print_rings((std::string(kEyes[e]) + " full gpu vs cpu").c_str(), rings);
    for (int ring = 0; ring < kRings; ++ring) {
      SCOPED_TRACE("ring " + std::to_string(kRingEdgesDeg[ring]) + " deg");
      EXPECT_GT(rings[ring].pixels, 0u);
      EXPECT_GE(rings[ring].psnr_db(), kMinPsnrDb);
      EXPECT_GE(rings[ring].share1(), kMinWithin1);
      EXPECT_GE(rings[ring].share2(), kMinWithin2);
    }
  }
}

TEST_F(HelloFoveatedMode, BothRunsFullThenFoveatedAndReportsTheirRatio) {
  const AppRun r = launch("both", {"--mode", "both", "--engine", "cpu"});
  ASSERT_EQ(r.process.exit_code, 0) << r.process.output;
  ASSERT_TRUE(r.stats.is_object()) << r.process.output;
  EXPECT_EQ(r.stats["mode"], "both");
  const auto& full = r.stats["full"];
  const auto& fov = r.stats["foveated"];
  ASSERT_TRUE(full.is_object()) << r.process.output;
  ASSERT_TRUE(fov.is_object()) << r.process.output;
  EXPECT_EQ(full["mode"], "full");
  EXPECT_EQ(fov["mode"], "foveated");
  EXPECT_EQ(full["layer_frames_traced"], 0);
  EXPECT_EQ(fov["frames_traced"], kFrames) << "the layer survived a session before and traced this one";
  EXPECT_EQ(fov["views_fallback"], 0);
  EXPECT_EQ(full["frames_rendered"], kFrames);
  EXPECT_EQ(fov["frames_rendered"], kFrames);
  for (int e = 0; e < 2; ++e) {
    SCOPED_TRACE(kEyes[e]);
    const uint64_t full_rays = full["rays_per_eye"][e].get<uint64_t>();
    const uint64_t fov_rays = fov["rays_per_eye"][e].get<uint64_t>();
    EXPECT_EQ(full_rays, uint64_t(kWidth) * kHeight * kRaysPerPixel);
    EXPECT_EQ(fov_rays, fov["eyes"][e]["rays"].get<uint64_t>()) << "the layer's own count";
    EXPECT_GT(fov_rays, 0u);
    EXPECT_LT(fov_rays, full_rays);
  }
  const auto& speedup = r.stats["speedup"];
  for (const char* key : {"frame_ms", "trace_ms"}) {
    SCOPED_TRACE(key);
    ASSERT_TRUE(speedup[key].is_number()) << speedup.dump();
    const double f = full[key].get<double>(), v = fov[key].get<double>(), s = speedup[key].get<double>();
    EXPECT_GT(f, 0.0);
    EXPECT_GT(v, 0.0);
    EXPECT_GT(s, 0.0);
    EXPECT_NEAR(s, f / v, 1e-9 * (f / v));
  }
  // Each eye's own median is there too.
  for (const auto* mode : {&full, &fov}) {
    EXPECT_GT((*mode)["trace_ms_per_eye"][0].get<double>(), 0.0);
    EXPECT_GT((*mode)["trace_ms_per_eye"][1].get<double>(), 0.0);
  }
}

TEST_F(HelloFoveatedMode, BadCombinationsExit2NamingTheOption) {
  struct Case {
    std::vector<std::string> args;
    const char* named;
  };
  for (const Case& c : std::vector<Case>{{{"--mode", "full", "--fault", "nan"}, "--fault"},
                                         {{"--mode", "both", "--engine", "gpu", "--fault", "error"}, "--fault"},
                                         {{"--mode", "full", "--temporal", "image"}, "--temporal"},
                                         {{"--mode", "full", "--engine", "gpu", "--temporal", "rays"}, "--temporal"}}) {
    std::vector<std::string> argv{FOVEART_HELLO_FOVEATED};
    argv.insert(argv.end(), c.args.begin(), c.args.end());
    const auto r = run_process(argv, env_->root() / "bad_args.log", 60);
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find(c.named), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("foveart-sim"), std::string::npos) << "rejected before any session: " << r.output;
  }
  // CLI11 rejects an unknown mode with its own message and exit code.
  const auto r = run_process({FOVEART_HELLO_FOVEATED, "--mode", "half"}, env_->root() / "bad_mode.log", 60);
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("--mode"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace foveart::layer::test
