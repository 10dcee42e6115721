// hello_foveated --engine gpu through the real loader, the layer and the
// simulated FOVE runtime on lavapipe: the GPU sample engine traces the layer's
// device rays (XrFoveatedDeviceTraceInfoFOVEART) and its foveated frames match
// those of the CPU engine's callback, reconstructed on the GPU as well, per
// eccentricity ring around the gaze; under Vulkan synchronization validation it
// stays silent; a device trace that fails, writes NaN or writes nothing makes
// the views fall back, counted, and the app exits normally; a trace that
// starts writing NaN after good frames shows the last good image, decided on
// the device, and is counted when the layer reads the frame's status.
//
// The setting. 320x360 eyes (lavapipe traces them in seconds), density
// scale 4: about 30.8k points per eye, pixel-exact (one point per pixel)
// inside about 10 deg of the gaze and sparse beyond, so the rings see both a
// dense fovea and an interpolated periphery (at scale 1 these small eyes get
// one point per pixel everywhere and the gaze would not matter); 2 rays per
// point, so the device resolve averages; temporal "off", so frames are
// deterministic; "reconstruction": "gpu" for both runs.
//
// The tolerance. Both runs foveate the same pixel with the same tables, seed,
// points and rays (the layer makes the device rays with the CPU's jitter in
// 32-bit words: the primary ray counts are equal), reconstruct on the GPU
// with the same shaders and encode to 8-bit sRGB. What differs is who traced:
// the GPU engine agrees with the CPU engine within 1e-3 relative per ray
// (tests/engine), from float rounding in ray setup, BVH traversal and shading
// order; the device resolve also sums a point's rays in its own order. A
// relative error e moves an sRGB value by about e * L * S'(L) * 255 steps, and
// L * S'(L) <= 1.055 / 2.4 = 0.44 on [0, 1] (0.04 on the linear segment; the
// tone curves compress further): 1e-3 is about 0.1 step, so a pixel moves by
// one step only where it sits at a rounding boundary. A ray grazing a
// silhouette could flip its hit and give one isolated large difference. So per ring
// (degrees of eccentricity from the gaze direction, cut by the exact angle of
// each pixel centre's direction through the view's FOV tangents):
//   PSNR >= 45 dB, >= 99 % of pixels within 1 step and >= 99.5 % within 2
//   steps (a pixel's worst channel).
// (The comparison and these bounds: ring_compare.hpp, shared with hello_foveated_mode_test.)
// Measured on lavapipe (LLVM 15): every ring of both eyes within 1 step, max
// difference 1, PSNR inf (rings < 10 deg) and 86-91 dB (beyond); the ray
// counts of every kind equal. The controls fail these bounds by far: the CPU
// engine with the gaze moved by one pixel gives 24-27 dB and 57-81 % within
// one step in the rings beyond 10 deg (inside, the pixel-exact fovea does not
// move: identical), and one ray per point instead of two (another sample
// set) gives 14-29 dB and 66-88 % in every ring. A wrong gaze, sample pattern
// or jitter on the device path therefore cannot pass.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "gpu_engine_run.hpp"
#include "ring_compare.hpp"

namespace foveart::layer::test {
namespace {

TEST_F(GpuEngine, FoveatedFramesMatchTheCpuEnginesPerEccentricityRing) {
  // Content density off (the GPU path's default thins from the second frame, and several rays
  // per point vary by contrast): the two engines' colours differ by float rounding, enough to
  // move a tile across a density level and a few points and rays with it.
  // AppRecordedContentDensityThinsAsTheCallbackModel compares both levers.
  configure_hello_foveated(*env_, kFrames, "gpu", {}, kContentDensityOff);
  const auto gaze = gaze_trace("gaze", kGaze[0], kGaze[1], kGaze[2]);
  const AppRun cpu = launch("cpu", "cpu", gaze);
  ASSERT_NO_FATAL_FAILURE(expect_clean(cpu, "cpu"));
  const AppRun gpu = launch("gpu", "gpu", gaze, {"--texture-lod", "off"});  // level 0, as the CPU engine
  ASSERT_NO_FATAL_FAILURE(expect_clean(gpu, "gpu"));

  // Who traced: the GPU engine, on the device, every ray; the CPU engine not once.
  const auto& cpu_rays = cpu.stats["engine_rays"];
  const auto& gpu_rays = gpu.stats["engine_rays"];
  std::printf("rays traced: cpu run: %s; gpu run: %s\n", cpu_rays.dump().c_str(), gpu_rays.dump().c_str());
  EXPECT_TRUE(cpu_rays["gpu"].is_null());
  EXPECT_GT(cpu_rays["cpu"]["primary"].get<uint64_t>(), 0u);
  ASSERT_TRUE(gpu_rays["gpu"].is_object()) << gpu.process.output;
  // hello_foveated enables bufferDeviceAddress through xrCreateVulkanDeviceKHR (lavapipe offers
  // it): the layer recorded it, so its batches chain the buffers' addresses besides the footprints.
  EXPECT_EQ(gpu.stats["gpu_engine"]["batch"]["footprints"], true) << gpu.process.output;
  EXPECT_EQ(gpu.stats["gpu_engine"]["batch"]["addresses"], true) << gpu.process.output;
  EXPECT_GT(gpu_rays["gpu"]["primary"].get<uint64_t>(), 0u);
  EXPECT_GT(gpu_rays["gpu"]["shadow"].get<uint64_t>(), 0u);
  EXPECT_EQ(total_rays(gpu_rays["cpu"]), 0u) << "the CPU engine traced during a device-trace run";
  // The same primary rays, all of them (one per point and ray of each traced view);
  // secondary rays follow hits, which float rounding may move at an edge.
  EXPECT_EQ(gpu_rays["gpu"]["primary"], cpu_rays["cpu"]["primary"]);
  for (const char* kind : {"shadow", "reflection", "refraction"}) {
    const double c = cpu_rays["cpu"][kind].get<double>(), g = gpu_rays["gpu"][kind].get<double>();
    EXPECT_NEAR(g, c, 1e-3 * c + 2.0) << kind;
  }
  for (int e = 0; e < 2; ++e) {
    EXPECT_EQ(gpu.stats["eyes"][e]["points"], cpu.stats["eyes"][e]["points"]) << "eye " << e;
    EXPECT_EQ(gpu.stats["eyes"][e]["rays"], cpu.stats["eyes"][e]["rays"]) << "eye " << e;
  }
  ASSERT_EQ(gpu.stats["gaze_px_per_frame"], cpu.stats["gaze_px_per_frame"]) << "both runs must foveate alike";

  const char* eyes[2] = {"left", "right"};
  const auto last = gpu.stats["gaze_px_per_frame"].back().get<std::vector<double>>();
  std::vector<double> fov[2];
  for (int e = 0; e < 2; ++e) {
    SCOPED_TRACE(eyes[e]);
    fov[e] = gpu.stats["views"][e]["fov_rad"].get<std::vector<double>>();
    const Rgb8 a = load_rgb(frame(cpu, kFrames - 1, eyes[e]));
    const Rgb8 b = load_rgb(frame(gpu, kFrames - 1, eyes[e]));
    ASSERT_EQ(a.width, kWidth);
    ASSERT_EQ(a.height, kHeight);
    ASSERT_EQ(b.width, kWidth);
    ASSERT_EQ(b.height, kHeight);
    const double gx = last[1 + 2 * e], gy = last[2 + 2 * e];
    ASSERT_GT(std::abs(gx - kWidth / 2.0) + std::abs(gy - kHeight / 2.0), 4.0) << "the gaze must be off the centre";
    const auto rings = compare_rings(a, b, fov[e], gx, gy);
    print_rings((std::string(eyes[e]) + " gpu vs cpu engine").c_str(), rings);
    for (int r = 0; r < kRings; ++r) {
      SCOPED_TRACE("ring " + std::to_string(kRingEdgesDeg[r]) + " deg");
      EXPECT_GT(rings[r].pixels, 0u);
      EXPECT_GE(rings[r].psnr_db(), kMinPsnrDb);
      EXPECT_GE(rings[r].share1(), kMinWithin1);
      EXPECT_GE(rings[r].share2(), kMinWithin2);
    }
  }

  // The controls, CPU engine, one frame (with temporal "off" each frame is
  // traced alike): what a wrong gaze and a wrong sample pattern would give.
  // (a) The gaze one pixel to the right (both eyes: the views are parallel).
  // Inside about 10 deg the point set is pixel-exact at these eyes (one point
  // per pixel), so the image there does not move; beyond it every peripheral
  // point moves: those rings must fail. (b) One ray per point instead of two:
  // another sample set, so edges change everywhere: every ring must fail.
  const double tl = std::tan(fov[0][0]), tr = std::tan(fov[0][1]);
  const double shift = (tr - tl) / kWidth;  // one pixel in tangent space
  const auto shifted = gaze_trace("gaze_shifted", kGaze[0] + shift * kGaze[2], kGaze[1], kGaze[2]);
  const AppRun moved = launch("control_gaze", "cpu", shifted, {}, 1);
  ASSERT_NO_FATAL_FAILURE(expect_clean(moved, "cpu", 1));
  const AppRun resampled = launch("control_rays", "cpu", gaze, {}, 1, 1);
  ASSERT_NO_FATAL_FAILURE(expect_clean(resampled, "cpu", 1));
  for (int e = 0; e < 2; ++e) {
    SCOPED_TRACE(eyes[e]);
    const auto moved_px = moved.stats["gaze_px_per_frame"].back().get<std::vector<double>>();
    EXPECT_NEAR(moved_px[1 + 2 * e] - last[1 + 2 * e], 1.0, 0.5) << "the control's gaze moves by one pixel";
    const Rgb8 b = load_rgb(frame(gpu, kFrames - 1, eyes[e]));
    const Rgb8 a = load_rgb(frame(moved, 0, eyes[e]));
    ASSERT_EQ(a.rgb.size(), b.rgb.size());
    const auto rings = compare_rings(a, b, fov[e], last[1 + 2 * e], last[2 + 2 * e]);
    print_rings((std::string(eyes[e]) + " gpu vs cpu, gaze +1 px").c_str(), rings);
    for (int r = 0; r < kRings; ++r) {
      if (kRingEdgesDeg[r] >= 10.0) {
        EXPECT_FALSE(rings[r].passes()) << "a 1 px gaze shift passes ring " << r;
      }
    }
    const Rgb8 c = load_rgb(frame(resampled, 0, eyes[e]));
    ASSERT_EQ(c.rgb.size(), b.rgb.size());
    const auto rings1 = compare_rings(c, b, fov[e], last[1 + 2 * e], last[2 + 2 * e]);
    print_rings((std::string(eyes[e]) + " gpu vs cpu, 1 ray/point").c_str(), rings1);
    for (int r = 0; r < kRings; ++r) EXPECT_FALSE(rings1[r].passes()) << "another sample pattern passes ring " << r;
  }
}

// The device-trace frame path under Vulkan validation with synchronization
// validation (as HelloFoveatedValidated): no message. Also with --fault nan,
// whose fill after the engine's dispatch needs its own barrier (without it,
// synchronization validation reports SYNC-HAZARD-WRITE-AFTER-WRITE): from the
// first frame ("nan": every frame waited for, as no good image is shown yet)
// and from frame 2 on ("late": pipelined frames, the fault kept on the device;
// frame 2's status is read at frame 4); with "temporal": "rays" ("rays"),
// the render cache fed by the device trace on the device, beside the path's default content
// density (the second frame thins by the first's tiles on the device, the cache takes the
// traced points' rays; XrFoveatedRendererDensityStatsFOVEART has its thinned points and
// passes' GPU ms); with the config's content density and rays per point by contrast
// ("density"); and with content density turned off by the config ("none": every stat 0).
class GpuEngineValidated : public GpuEngine, public ::testing::WithParamInterface<const char*> {};

// XrFoveatedRendererDensityStatsFOVEART through hello_foveated --json on a device trace: with
// content density on, the newest finished frame thinned points and the device's passes are
// timed, while the host's stages stay 0 (the CPU's test, observe and fill do not run); off,
// everything is 0.
void expect_device_density_stats(const AppRun& r, bool density_on) {
  const nlohmann::json& d = r.stats["density"];
  ASSERT_TRUE(d.is_object()) << r.process.output;
  for (int e = 0; e < 2; ++e) {
    const nlohmann::json& eye = d["eyes"][e];
    std::cout << "[ measured ] eye " << e << " density stats " << eye.dump() << "\n";
    for (const char* host : {"levels_ms", "test_ms", "observe_ms", "fill_ms"})
      EXPECT_EQ(eye[host].get<double>(), 0.0) << "eye " << e << " " << host;
    if (!density_on) {
      for (const char* key : {"points_thinned", "gpu_fill_ms", "gpu_contrast_ms"})
        EXPECT_EQ(eye[key].get<double>(), 0.0) << "eye " << e << " " << key;
      continue;
    }
    EXPECT_GT(eye["points_thinned"].get<uint64_t>(), 0u) << "eye " << e;
    EXPECT_GT(eye["gpu_fill_ms"].get<double>(), 0.0) << "eye " << e;
    EXPECT_GT(eye["gpu_contrast_ms"].get<double>(), 0.0) << "eye " << e;
    EXPECT_GT(d["per_frame"]["gpu_contrast_ms"][e]["count"].get<int>(), 0) << "eye " << e;
  }
}

TEST_P(GpuEngineValidated, DeviceTraceUnderSynchronizationValidationHasNoErrors) {
  const std::string fault = GetParam();
  const auto gaze = gaze_trace("gaze", kGaze[0], kGaze[1], kGaze[2]);
  IsolatedEnv::set("XR_API_LAYER_PATH", (explicit_layer_dir().string() + ":" + kSystemExplicitLayers).c_str());
  IsolatedEnv::set("XR_ENABLE_API_LAYERS", "XR_APILAYER_FOVEART_foveated_ray_tracing:XR_APILAYER_LUNARG_core_validation");
  IsolatedEnv::set("VK_INSTANCE_LAYERS", "VK_LAYER_KHRONOS_validation");
  IsolatedEnv::set("VK_LAYER_PATH", "/usr/share/vulkan/explicit_layer.d");
  IsolatedEnv::set("VK_LAYER_ENABLES", "VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT");
  IsolatedEnv::set("XR_LOADER_DEBUG", "info");
  IsolatedEnv::set("VK_LOADER_DEBUG", "layer");
  std::vector<std::string> extra{"--no-explicit-layer"};
  const bool rays = fault == "rays";  // no fault; the render cache fed by the device trace, on the device
  const bool density = fault == "density";  // no fault; the config's content density on the device trace
  if (density) configure_hello_foveated(*env_, kFrames, "gpu", {}, R"("content_contrast": 0.1, "content_rays": 0.2)");
  if (fault == "none") configure_hello_foveated(*env_, kFrames, "gpu", {}, kContentDensityOff);
  if (fault == "nan") extra.insert(extra.end(), {"--fault", fault});
  if (fault == "late") extra.insert(extra.end(), {"--fault", "nan", "--fault-from-frame", "2"});
  // "late", and the thinning runs so that the stats hold frame 2, the first that thins (read when its slot
  // comes round).
  constexpr int kLateFrames = 4;
  const bool thins = rays || density;
  const int frames = fault == "late" || thins ? kLateFrames : kFrames;
  const AppRun r = launch("validated", "gpu", gaze, extra, frames, kRaysPerPoint, rays || density ? "rays" : "off");
  for (const char* name : {"XR_ENABLE_API_LAYERS", "VK_INSTANCE_LAYERS", "VK_LAYER_PATH", "VK_LAYER_ENABLES",
                           "XR_LOADER_DEBUG", "VK_LOADER_DEBUG"}) {
    ::unsetenv(name);
  }
  if (fault == "none" || rays || density) {
    ASSERT_NO_FATAL_FAILURE(expect_clean(r, "gpu", frames, rays || density ? "rays" : "off"));
    ASSERT_NO_FATAL_FAILURE(expect_device_density_stats(r, thins));
  } else if (fault == "late") {
    ASSERT_EQ(r.process.exit_code, 0) << r.process.output;
    ASSERT_TRUE(r.stats.is_object()) << r.process.output;
    EXPECT_EQ(r.stats["frames_traced"], kLateFrames);
    EXPECT_EQ(r.stats["views_fallback"], 2);
    EXPECT_GT(r.stats["invalid_colours"].get<int>(), 0);
  } else {
    ASSERT_EQ(r.process.exit_code, 0) << r.process.output;
    ASSERT_TRUE(r.stats.is_object()) << r.process.output;
    EXPECT_EQ(r.stats["views_fallback"], 2 * kFrames);
    EXPECT_GT(r.stats["invalid_colours"].get<int>(), 0);
  }
  EXPECT_GT(r.stats["engine_rays"]["gpu"]["primary"].get<uint64_t>(), 0u);
  for (const char* loaded : {"succeeded loading layer XR_APILAYER_LUNARG_core_validation",
                             "Insert instance layer \"VK_LAYER_KHRONOS_validation\""}) {
    EXPECT_NE(r.process.output.find(loaded), std::string::npos) << "missing: " << loaded;
  }
  for (const char* marker : {"Validation Error", "VUID-", "VALID_ERROR", "SYNC-HAZARD", "Validation Warning"}) {
    EXPECT_EQ(r.process.output.find(marker), std::string::npos) << marker << " in:\n" << r.process.output;
  }
}

// "rays": no fault, "temporal": "rays": the render cache runs on the device trace's rays (not downgraded to
// "image", as the stats say), silently under synchronization validation.
INSTANTIATE_TEST_SUITE_P(Faults, GpuEngineValidated, ::testing::Values("none", "nan", "late", "rays", "density"),
                         [](const ::testing::TestParamInfo<const char*>& p) { return std::string(p.param); });

// A device trace that fails: every view falls back to the app's grey
// placeholder, counted, logged once; the app exits 0.
class FailingDeviceTrace : public GpuEngine, public ::testing::WithParamInterface<const char*> {};

TEST_P(FailingDeviceTrace, ViewsFallBackCountedAndTheAppExitsNormally) {
  const auto gaze = gaze_trace("gaze", kGaze[0], kGaze[1], kGaze[2]);
  const std::string fault = GetParam();
  const AppRun r = launch("fault", "gpu", gaze, {"--fault", fault});
  ASSERT_EQ(r.process.exit_code, 0) << r.process.output;
  ASSERT_TRUE(r.stats.is_object()) << r.process.output;
  EXPECT_EQ(r.stats["engine"], "gpu");
  EXPECT_EQ(r.stats["frames_traced"], 0);
  EXPECT_EQ(r.stats["views_fallback"], 2 * kFrames);
  if (fault == "error") {
    EXPECT_EQ(r.stats["callback_failures"], 2 * kFrames);
    EXPECT_EQ(r.stats["invalid_colours"], 0);
  } else {
    EXPECT_EQ(r.stats["callback_failures"], 0);
    EXPECT_GT(r.stats["invalid_colours"].get<int>(), 0);
  }
  // The device trace was the one failing: the CPU callback never ran instead.
  EXPECT_EQ(total_rays(r.stats["engine_rays"]["cpu"]), 0u);
  std::size_t lines = 0;
  for (std::size_t at = r.process.output.find("logged once"); at != std::string::npos;
       at = r.process.output.find("logged once", at + 1)) {
    ++lines;
  }
  EXPECT_EQ(lines, 1u) << r.process.output;
  for (const char* eye : {"left", "right"}) {
    const Rgb8 img = load_rgb(frame(r, kFrames - 1, eye));
    ASSERT_EQ(img.width, kWidth) << eye;
    const auto [lo, hi] = std::minmax_element(img.rgb.begin(), img.rgb.end());
    EXPECT_NEAR(*lo, 124, 1) << "the app's grey placeholder, " << eye;
    EXPECT_NEAR(*hi, 124, 1) << "the app's grey placeholder, " << eye;
  }
}

INSTANTIATE_TEST_SUITE_P(Faults, FailingDeviceTrace, ::testing::Values("error", "nan", "nothing"),
                         [](const ::testing::TestParamInfo<const char*>& p) { return std::string(p.param); });

// A device trace that writes NaN from the layer's frame 4 on, after three good
// frames. The layer does not wait for those frames (two in flight): the device
// finds the fault (the resolve's status) and keeps each eye's last good image,
// so every faulted frame shows exactly frame 3's image (temporal "off", a
// static head and gaze: the good frames are alike). Shown, the faulted frame
// would differ: the NaN ray's point spreads NaN through the gather, which the
// encode writes as black (with the temporal pass and the encode ignoring the
// status, this test fails on every faulted frame). The host reads frame 4's status when its slot comes
// round, at frame 6: that frame's two views are counted as fallbacks, and
// frames 5 and 6 are still in flight when the app reads the stats.
TEST_F(GpuEngine, AFaultAfterGoodFramesShowsTheLastGoodImage) {
  constexpr int kRun = 6, kFirstFault = 4;  // the layer's frame indices count from 1
  // Content density off, so that the good frames are alike (it thins from the second frame).
  configure_hello_foveated(*env_, kRun, "gpu", {}, kContentDensityOff);
  const auto gaze = gaze_trace("gaze", kGaze[0], kGaze[1], kGaze[2]);
  const AppRun r = launch("late_fault", "gpu", gaze,
                          {"--fault", "nan", "--fault-from-frame", std::to_string(kFirstFault)}, kRun);
  ASSERT_EQ(r.process.exit_code, 0) << r.process.output;
  ASSERT_TRUE(r.stats.is_object()) << r.process.output;
  EXPECT_EQ(r.stats["frames_traced"], kRun) << "every view shows the layer's image";
  EXPECT_EQ(r.stats["views_fallback"], 2) << "frame 4's two views, read at frame 6";
  EXPECT_GT(r.stats["invalid_colours"].get<int>(), 0);
  EXPECT_EQ(r.stats["callback_failures"], 0);
  for (const char* eye : {"left", "right"}) {
    SCOPED_TRACE(eye);
    const Rgb8 good = load_rgb(frame(r, kFirstFault - 2, eye));  // capture indices count from 0
    ASSERT_EQ(good.width, kWidth);
    const auto [lo, hi] = std::minmax_element(good.rgb.begin(), good.rgb.end());
    EXPECT_GT(*hi - *lo, 16) << "a traced image, not the app's grey placeholder";
    EXPECT_EQ(load_rgb(frame(r, 0, eye)).rgb, good.rgb) << "the good frames are alike";
    for (int f = kFirstFault - 1; f < kRun; ++f) {
      const Rgb8 shown = load_rgb(frame(r, f, eye));
      ASSERT_EQ(shown.rgb.size(), good.rgb.size()) << "frame " << f;
      EXPECT_TRUE(shown.rgb == good.rgb) << "faulted frame " << f << " is not the last good image";
    }
  }
}

// Bad arguments: a clear message and a non-zero exit, before any session.
TEST_F(GpuEngine, FaultsOfTheOtherEngineAreRejected) {
  for (const auto& args : std::vector<std::vector<std::string>>{{"--engine", "gpu", "--fault", "throw"},
                                                               {"--engine", "cpu", "--fault", "nothing"},
                                                               {"--engine", "vulkan"}}) {
    std::vector<std::string> argv{FOVEART_HELLO_FOVEATED};
    argv.insert(argv.end(), args.begin(), args.end());
    const auto r = run_process(argv, env_->root() / "bad_args.log", 60);
    EXPECT_NE(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find(args.back()), std::string::npos) << r.output;
  }
}

}  // namespace
}  // namespace foveart::layer::test
