// hello_foveated --engine gpu --trace-model app through the real loader, the
// layer and the simulated runtime on lavapipe: the app acquires each frame's
// ray batch, records the GPU engine's trace in its own command buffer, submits
// it with the batch's timeline wait and signal and releases the batch (the
// extension header's app-recorded trace).
//
// Its frames equal the callback model's (the layer records the same engine's
// trace inside xrEndFrame) within one 8-bit step: the same rays (made by the
// same shader from the same gaze and seed), traced by the same engine with the
// same commands, resolved and reconstructed by the same shaders; only who
// records and submits the trace differs, so any pixel off by more than one
// step is a different frame; with content density too, whose tiles the acquire's
// rays read. Under synchronization validation the model is silent, over more
// frames than slots (each slot reused). A batch never
// released, or an unknown id released instead, is an XrResult error and the
// views fall back, counted; a second release is refused while the frame is traced.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "gpu_engine_run.hpp"

namespace foveart::layer::test {
namespace {

constexpr int kPipelinedFrames = 4;  // two frame slots, each used twice

// The largest difference of any channel of any pixel; -1 when the sizes differ.
int max_step(const Rgb8& a, const Rgb8& b) {
  if (a.width != b.width || a.height != b.height || a.rgb.size() != b.rgb.size()) return -1;
  int worst = 0;
  for (std::size_t i = 0; i < a.rgb.size(); ++i) worst = std::max(worst, std::abs(int(a.rgb[i]) - int(b.rgb[i])));
  return worst;
}

// A traced image, not the app's uniform grey placeholder.
bool traced_image(const Rgb8& img) {
  const auto [lo, hi] = std::minmax_element(img.rgb.begin(), img.rgb.end());
  return img.width > 0 && *hi - *lo > 16;
}

// Every captured frame of both eyes: `expected`'s is traced, and `actual`'s is within one step of it.
void expect_frames_within_one_step(const AppRun& expected, const AppRun& actual) {
  for (int f = 0; f < kPipelinedFrames; ++f) {
    for (const char* eye : {"left", "right"}) {
      SCOPED_TRACE(std::string(eye) + ", frame " + std::to_string(f));
      const Rgb8 a = load_rgb(captured_frame(expected.frames, f, eye));
      const Rgb8 b = load_rgb(captured_frame(actual.frames, f, eye));
      ASSERT_TRUE(traced_image(a));
      EXPECT_GE(max_step(a, b), 0) << "the sizes differ";
      EXPECT_LE(max_step(a, b), 1);
    }
  }
}

void expect_app_trace(const AppRun& r, int acquired, int unreleased, int rejected, int release_errors) {
  ASSERT_TRUE(r.stats["app_trace"].is_object()) << r.process.output;
  const auto& a = r.stats["app_trace"];
  EXPECT_EQ(r.stats["trace_model"], "app");
  EXPECT_EQ(a["batches_acquired"], acquired);
  EXPECT_EQ(a["unreleased_batches"], unreleased);
  EXPECT_EQ(a["rejected_releases"], rejected);
  EXPECT_EQ(a["release_errors"], release_errors);
  EXPECT_EQ(a["mismatched_views"], 0);
}

TEST_F(GpuEngine, AppRecordedFramesEqualTheCallbackModelsWithinOneStep) {
  const auto gaze = gaze_trace("gaze", kGaze[0], kGaze[1], kGaze[2]);
  const AppRun callback = launch("callback", "gpu", gaze, {}, kPipelinedFrames);
  ASSERT_NO_FATAL_FAILURE(expect_clean(callback, "gpu", kPipelinedFrames));
  EXPECT_EQ(callback.stats["trace_model"], "callback");
  EXPECT_FALSE(callback.stats.contains("app_trace")) << "the callback model acquires nothing";
  const AppRun app = launch("app", "gpu", gaze, {"--trace-model", "app"}, kPipelinedFrames);
  ASSERT_NO_FATAL_FAILURE(expect_clean(app, "gpu", kPipelinedFrames));
  ASSERT_NO_FATAL_FAILURE(expect_app_trace(app, kPipelinedFrames, 0, 0, 0));
  std::printf("app-recorded trace: %s\n", app.stats["app_trace"].dump().c_str());
  EXPECT_EQ(app.stats["app_trace"]["acquire_to_end_frame_ms"]["count"], kPipelinedFrames);
  EXPECT_GT(app.stats["app_trace"]["acquire_to_end_frame_ms"]["p50"].get<double>(), 0.0)
      << "the rays' gaze is older than xrEndFrame's by the app's trace";
  // The same engine traced the same rays, once per ray.
  EXPECT_EQ(app.stats["engine_rays"]["gpu"]["primary"], callback.stats["engine_rays"]["gpu"]["primary"]);
  EXPECT_EQ(app.stats["gaze_px_per_frame"], callback.stats["gaze_px_per_frame"]);
  expect_frames_within_one_step(callback, app);
}

// With content density beside the render cache (the GPU path's default history), the
// acquire's rays read the tiles the last frame's xrEndFrame measured, as the callback
// model's rays do inside xrEndFrame: the same points thinned, the same rays traced, the
// frames within one step. Frame 2 on thins (the first has no contrast yet).
TEST_F(GpuEngine, AppRecordedContentDensityThinsAsTheCallbackModel) {
  const auto gaze = gaze_trace("gaze", kGaze[0], kGaze[1], kGaze[2]);
  configure_hello_foveated(*env_, kPipelinedFrames, "gpu", {}, R"("content_contrast": 0.1, "content_rays": 0.2)");
  const AppRun callback = launch("callback_density", "gpu", gaze, {}, kPipelinedFrames, kRaysPerPoint, "rays");
  ASSERT_NO_FATAL_FAILURE(expect_clean(callback, "gpu", kPipelinedFrames, "rays"));
  const AppRun app =
      launch("app_density", "gpu", gaze, {"--trace-model", "app"}, kPipelinedFrames, kRaysPerPoint, "rays");
  ASSERT_NO_FATAL_FAILURE(expect_clean(app, "gpu", kPipelinedFrames, "rays"));
  ASSERT_NO_FATAL_FAILURE(expect_app_trace(app, kPipelinedFrames, 0, 0, 0));
  for (int e = 0; e < 2; ++e) {
    const uint64_t thinned = app.stats["density"]["eyes"][e]["points_thinned"].get<uint64_t>();
    std::printf("eye %d: %llu points thinned, app-recorded; callback model: %s\n", e,
                static_cast<unsigned long long>(thinned),
                callback.stats["density"]["eyes"][e]["points_thinned"].dump().c_str());
    EXPECT_GT(thinned, 0u) << "eye " << e;
    EXPECT_EQ(app.stats["density"]["eyes"][e]["points_thinned"], callback.stats["density"]["eyes"][e]["points_thinned"])
        << "eye " << e;
  }
  EXPECT_EQ(app.stats["engine_rays"]["gpu"]["primary"], callback.stats["engine_rays"]["gpu"]["primary"]);
  expect_frames_within_one_step(callback, app);
}

// As GpuEngineValidated: the layers loaded, no message; over more frames than
// slots, with batches never released ("never": the layer waits for no value,
// the app still signals the retired semaphore, later batches use a new one), and
// with content density beside the render cache ("density": the acquire's rays
// read the tiles the last frame's submission wrote).
class AppTraceValidated : public GpuEngine, public ::testing::WithParamInterface<const char*> {};

TEST_P(AppTraceValidated, AppRecordedTraceUnderSynchronizationValidationHasNoErrors) {
  const std::string fault = GetParam();
  const auto gaze = gaze_trace("gaze", kGaze[0], kGaze[1], kGaze[2]);
  IsolatedEnv::set("XR_API_LAYER_PATH", (explicit_layer_dir().string() + ":" + kSystemExplicitLayers).c_str());
  IsolatedEnv::set("XR_ENABLE_API_LAYERS",
                   "XR_APILAYER_FOVEART_foveated_ray_tracing:XR_APILAYER_LUNARG_core_validation");
  IsolatedEnv::set("VK_INSTANCE_LAYERS", "VK_LAYER_KHRONOS_validation");
  IsolatedEnv::set("VK_LAYER_PATH", "/usr/share/vulkan/explicit_layer.d");
  IsolatedEnv::set("VK_LAYER_ENABLES", "VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT");
  IsolatedEnv::set("XR_LOADER_DEBUG", "info");
  IsolatedEnv::set("VK_LOADER_DEBUG", "layer");
  std::vector<std::string> extra{"--no-explicit-layer", "--trace-model", "app"};
  const bool density = fault == "density";  // no fault: content density beside the render cache
  if (density) {
    configure_hello_foveated(*env_, kPipelinedFrames, "gpu", {}, R"("content_contrast": 0.1, "content_rays": 0.2)");
  } else if (fault != "none") {
    extra.insert(extra.end(), {"--release-fault", fault});
  }
  const char* temporal = density ? "rays" : "off";
  const AppRun r = launch("validated_app", "gpu", gaze, extra, kPipelinedFrames, kRaysPerPoint, temporal);
  for (const char* name : {"XR_ENABLE_API_LAYERS", "VK_INSTANCE_LAYERS", "VK_LAYER_PATH", "VK_LAYER_ENABLES",
                           "XR_LOADER_DEBUG", "VK_LOADER_DEBUG"}) {
    ::unsetenv(name);
  }
  if (fault == "none" || density) {
    ASSERT_NO_FATAL_FAILURE(expect_clean(r, "gpu", kPipelinedFrames, temporal));
    ASSERT_NO_FATAL_FAILURE(expect_app_trace(r, kPipelinedFrames, 0, 0, 0));
    for (int e = 0; e < 2 && density; ++e)
      EXPECT_GT(r.stats["density"]["eyes"][e]["points_thinned"].get<uint64_t>(), 0u) << "eye " << e;
  } else {
    ASSERT_EQ(r.process.exit_code, 0) << r.process.output;
    ASSERT_NO_FATAL_FAILURE(expect_app_trace(r, kPipelinedFrames, kPipelinedFrames, 0, 0));
    EXPECT_EQ(r.stats["views_fallback"], 2 * kPipelinedFrames);
  }
  for (const char* loaded : {"succeeded loading layer XR_APILAYER_LUNARG_core_validation",
                             "Insert instance layer \"VK_LAYER_KHRONOS_validation\""}) {
    EXPECT_NE(r.process.output.find(loaded), std::string::npos) << "missing: " << loaded;
  }
  for (const char* marker : {"Validation Error", "VUID-", "VALID_ERROR", "SYNC-HAZARD", "Validation Warning"}) {
    EXPECT_EQ(r.process.output.find(marker), std::string::npos) << marker << " in:\n" << r.process.output;
  }
}

INSTANTIATE_TEST_SUITE_P(Faults, AppTraceValidated, ::testing::Values("none", "never", "density"),
                         [](const ::testing::TestParamInfo<const char*>& p) { return std::string(p.param); });

// A batch the app never releases (never), or in whose place it releases an
// unknown id (unknown): its views show the app's grey placeholder, counted,
// the batch retired and logged once; the app's next acquire works. A second
// release of a released batch (twice) is refused and retires it the same way. A
// batch acquired for other views than those submitted (moved): each view
// falls back, counted as mismatched. Views the layer cannot trace (nan): no
// rays, each view falls back, logged once.
class AppTraceRelease : public GpuEngine, public ::testing::WithParamInterface<const char*> {};

TEST_P(AppTraceRelease, ErrorsAreXrResultsAndUnreleasedViewsFallBackCounted) {
  const std::string fault = GetParam();
  const auto gaze = gaze_trace("gaze", kGaze[0], kGaze[1], kGaze[2]);
  const AppRun r = launch("release_" + fault, "gpu", gaze, {"--trace-model", "app", "--release-fault", fault});
  ASSERT_EQ(r.process.exit_code, 0) << r.process.output;
  ASSERT_TRUE(r.stats.is_object()) << r.process.output;
  if (fault == "nan") {  // views the layer cannot trace: no rays, each view falls back, logged once
    EXPECT_EQ(r.stats["app_trace"]["unreleased_batches"], 0);
    EXPECT_EQ(r.stats["frames_traced"], 0);
    EXPECT_EQ(r.stats["views_fallback"], 2 * kFrames);
    EXPECT_NE(r.process.output.find("xrAcquireFoveatedRayBatchFOVEART: eye 0: its view cannot be traced: position"),
              std::string::npos)
        << r.process.output;
    EXPECT_FALSE(traced_image(load_rgb(frame(r, kFrames - 1, "left"))));
    return;
  }
  if (fault == "moved") {
    EXPECT_EQ(r.stats["app_trace"]["mismatched_views"], 2 * kFrames);
    EXPECT_EQ(r.stats["app_trace"]["unreleased_batches"], 0);
    EXPECT_EQ(r.stats["frames_traced"], 0);
    EXPECT_EQ(r.stats["views_fallback"], 2 * kFrames);
    EXPECT_FALSE(traced_image(load_rgb(frame(r, kFrames - 1, "left"))));
    return;
  }
  const int errors = fault == "never" ? 0 : kFrames;
  ASSERT_NO_FATAL_FAILURE(expect_app_trace(r, kFrames, kFrames, errors, errors));
  constexpr int kValidationFailure = -1;  // XR_ERROR_VALIDATION_FAILURE
  if (errors > 0) {
    EXPECT_EQ(r.stats["app_trace"]["last_release_error"], kValidationFailure);
  }
  EXPECT_EQ(r.stats["frames_traced"], 0);
  EXPECT_EQ(r.stats["views_fallback"], 2 * kFrames) << "every retired batch's views counted";
  const char* logged = fault == "twice" ? "was released twice" : "was not released";
  EXPECT_NE(r.process.output.find(logged), std::string::npos) << r.process.output;
  for (const char* eye : {"left", "right"}) {
    EXPECT_FALSE(traced_image(load_rgb(frame(r, kFrames - 1, eye)))) << eye;
  }
}

INSTANTIATE_TEST_SUITE_P(Faults, AppTraceRelease, ::testing::Values("never", "twice", "unknown", "moved", "nan"),
                         [](const ::testing::TestParamInfo<const char*>& p) { return std::string(p.param); });

// Bad arguments: a clear message and a non-zero exit, before any session.
TEST_F(GpuEngine, AppTraceModelNeedsTheGpuEngine) {
  for (const auto& args : std::vector<std::vector<std::string>>{{"--engine", "cpu", "--trace-model", "app"},
                                                                {"--engine", "gpu", "--release-fault", "never"}}) {
    std::vector<std::string> argv{FOVEART_HELLO_FOVEATED};
    argv.insert(argv.end(), args.begin(), args.end());
    const auto r = run_process(argv, env_->root() / "bad_args.log", 60);
    EXPECT_NE(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find(args[2]), std::string::npos) << r.output;
  }
}

}  // namespace
}  // namespace foveart::layer::test
