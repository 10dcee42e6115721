// What a runtime's conformance suite would send through the layer, with the
// real loader, the simulated FOVE runtime and lavapipe: NULL frame infos,
// unknown handles, too many views, rects outside the swapchain, no RGBA8
// format, sessions in sequence, a renderer destroyed during its table build,
// a view size changing every frame. Plus the layer's own reporting: cache
// problems, failed builds and a backward gaze are logged once and counted.
#include <gtest/gtest.h>

#include <chrono>
#include <fstream>
#include <functional>
#include <limits>
#include <thread>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "layer/XR_FOVEART_foveated_ray_tracing.h"
#include "test_env.hpp"
#include "xr_test_app.h"

namespace foveart::layer::test {
namespace {

using sim::test::xr;
using sim::test::XrTestApp;

int32_t grey(void*, const FoveartRayBatch* batch) {
  for (uint32_t i = 0; i < 3 * batch->ray_count; ++i) batch->out_rgb[i] = 0.5f;
  return FOVEART_RESULT_SUCCESS;
}

std::string read_text(const fs::path& f) {
  std::ifstream in(f);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::size_t count_of(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

// An app on the layer: instance with the extension, a Vulkan session in
// FOCUSED, a LOCAL space, one 256x256 RGBA8 swapchain (released once), and
// helpers to submit one projection layer and read the stats.
class LayerApp {
 public:
  explicit LayerApp(const IsolatedEnv& env, const std::string& config_json = "{}") : env_(env) {
    std::ofstream(env.root() / "config.json") << config_json;
    IsolatedEnv::set("FOVEART_CONFIG", env.root() / "config.json");
    IsolatedEnv::set("XR_ENABLE_API_LAYERS", XR_FOVEART_API_LAYER_NAME);
  }
  ~LayerApp() { end_session(); }

  void start() {
    ASSERT_EQ(app.create_instance(false, {XR_FOVEART_FOVEATED_RAY_TRACING_EXTENSION_NAME}), XR_SUCCESS);
    create = app.proc<PFN_xrCreateFoveatedRendererFOVEART>("xrCreateFoveatedRendererFOVEART");
    destroy = app.proc<PFN_xrDestroyFoveatedRendererFOVEART>("xrDestroyFoveatedRendererFOVEART");
    get_stats = app.proc<PFN_xrGetFoveatedRendererStatsFOVEART>("xrGetFoveatedRendererStatsFOVEART");
    ASSERT_TRUE(create && destroy && get_stats);
    start_session();
  }

  void start_session() {
    ASSERT_EQ(app.create_session(), XR_SUCCESS);
    ASSERT_TRUE(app.run_until_state(XR_SESSION_STATE_FOCUSED));
    auto space_info = xr<XrReferenceSpaceCreateInfo>(XR_TYPE_REFERENCE_SPACE_CREATE_INFO);
    space_info.referenceSpaceType = XR_REFERENCE_SPACE_TYPE_LOCAL;
    space_info.poseInReferenceSpace.orientation.w = 1.0f;
    ASSERT_EQ(xrCreateReferenceSpace(app.session, &space_info, &space), XR_SUCCESS);
    uint32_t count = 0;
    ASSERT_EQ(xrEnumerateSwapchainFormats(app.session, 0, &count, nullptr), XR_SUCCESS);
    std::vector<int64_t> formats(count);
    ASSERT_EQ(xrEnumerateSwapchainFormats(app.session, count, &count, formats.data()), XR_SUCCESS);
    auto sc = xr<XrSwapchainCreateInfo>(XR_TYPE_SWAPCHAIN_CREATE_INFO);
    sc.usageFlags = XR_SWAPCHAIN_USAGE_COLOR_ATTACHMENT_BIT | XR_SWAPCHAIN_USAGE_TRANSFER_DST_BIT;
    sc.format = formats.front();
    sc.sampleCount = sc.faceCount = sc.arraySize = sc.mipCount = 1;
    sc.width = sc.height = swapchain_px;
    ASSERT_EQ(xrCreateSwapchain(app.session, &sc, &swapchain), XR_SUCCESS);
    uint32_t index = 0;
    auto acquire = xr<XrSwapchainImageAcquireInfo>(XR_TYPE_SWAPCHAIN_IMAGE_ACQUIRE_INFO);
    ASSERT_EQ(xrAcquireSwapchainImage(swapchain, &acquire, &index), XR_SUCCESS);
    auto wait = xr<XrSwapchainImageWaitInfo>(XR_TYPE_SWAPCHAIN_IMAGE_WAIT_INFO);
    wait.timeout = XR_INFINITE_DURATION;
    ASSERT_EQ(xrWaitSwapchainImage(swapchain, &wait), XR_SUCCESS);
    auto release = xr<XrSwapchainImageReleaseInfo>(XR_TYPE_SWAPCHAIN_IMAGE_RELEASE_INFO);
    ASSERT_EQ(xrReleaseSwapchainImage(swapchain, &release), XR_SUCCESS);
  }

  void end_session() {
    if (app.session == XR_NULL_HANDLE) return;
    if (swapchain != XR_NULL_HANDLE) xrDestroySwapchain(swapchain);
    if (space != XR_NULL_HANDLE) xrDestroySpace(space);
    xrDestroySession(app.session);
    swapchain = XR_NULL_HANDLE;
    space = XR_NULL_HANDLE;
    app.session = XR_NULL_HANDLE;
    app.state = XR_SESSION_STATE_UNKNOWN;
  }

  XrFoveatedRendererFOVEART make_renderer(const char* gaze_spec = nullptr, bool eye_gaze_interaction = false,
                                          XrFoveatedTemporalFOVEART temporal = XR_FOVEATED_TEMPORAL_OFF_FOVEART) {
    auto info = xr<XrFoveatedRendererCreateInfoFOVEART>(XR_TYPE_FOVEATED_RENDERER_CREATE_INFO_FOVEART);
    info.traceRays = &grey;
    info.interpolation = XR_FOVEATED_INTERPOLATION_NEAREST_FOVEART;
    info.k = 1;
    info.densityScale = 1.0f;
    info.raysPerPoint = 1;
    info.temporal = temporal;
    info.gazeSource = gaze_spec ? XR_FOVEATED_GAZE_SOURCE_PROVIDER_FOVEART : XR_FOVEATED_GAZE_SOURCE_NONE_FOVEART;
    info.gazeProviderSpec = gaze_spec;
    if (eye_gaze_interaction) info.gazeSource = XR_FOVEATED_GAZE_SOURCE_EYE_GAZE_INTERACTION_FOVEART;
    XrFoveatedRendererFOVEART renderer = XR_NULL_HANDLE;
    EXPECT_EQ(create(app.session, &info, &renderer), XR_SUCCESS);
    return renderer;
  }

  // One frame with one projection layer of view_count views, each showing
  // `rect` of the swapchain, opted in for `renderer` (XR_NULL_HANDLE: not opted in).
  XrResult frame(XrFoveatedRendererFOVEART renderer, XrRect2Di rect, uint32_t view_count = 2, float half_fov_rad = 0.7f,
                 const std::function<void(XrCompositionLayerProjectionView&)>& edit_first_view = {}) {
    auto wait = xr<XrFrameWaitInfo>(XR_TYPE_FRAME_WAIT_INFO);
    auto state = xr<XrFrameState>(XR_TYPE_FRAME_STATE);
    if (XrResult r = xrWaitFrame(app.session, &wait, &state); XR_FAILED(r)) return r;
    auto begin = xr<XrFrameBeginInfo>(XR_TYPE_FRAME_BEGIN_INFO);
    if (XrResult r = xrBeginFrame(app.session, &begin); XR_FAILED(r)) return r;
    std::vector<XrCompositionLayerProjectionView> views(view_count, xr<XrCompositionLayerProjectionView>(XR_TYPE_COMPOSITION_LAYER_PROJECTION_VIEW));
    for (uint32_t v = 0; v < view_count; ++v) {
      views[v].pose.orientation.w = 1.0f;
      views[v].pose.position.x = v == 0 ? -0.032f : 0.032f;
      views[v].fov = {-half_fov_rad, half_fov_rad, half_fov_rad, -half_fov_rad};
      views[v].subImage.swapchain = swapchain;
      views[v].subImage.imageRect = rect;
    }
    if (edit_first_view) edit_first_view(views[0]);
    auto opt_in = xr<XrFoveatedRayTracingLayerFOVEART>(XR_TYPE_FOVEATED_RAY_TRACING_LAYER_FOVEART);
    opt_in.renderer = renderer;
    auto projection = xr<XrCompositionLayerProjection>(XR_TYPE_COMPOSITION_LAYER_PROJECTION);
    projection.next = renderer == XR_NULL_HANDLE ? nullptr : &opt_in;
    projection.space = space;
    projection.viewCount = view_count;
    projection.views = views.data();
    const XrCompositionLayerBaseHeader* layers[] = {reinterpret_cast<XrCompositionLayerBaseHeader*>(&projection)};
    auto end = xr<XrFrameEndInfo>(XR_TYPE_FRAME_END_INFO);
    end.displayTime = state.predictedDisplayTime;
    end.environmentBlendMode = XR_ENVIRONMENT_BLEND_MODE_OPAQUE;
    end.layerCount = 1;
    end.layers = layers;
    return xrEndFrame(app.session, &end);
  }

  struct Stats {
    XrFoveatedRendererStatsFOVEART main = xr<XrFoveatedRendererStatsFOVEART>(XR_TYPE_FOVEATED_RENDERER_STATS_FOVEART);
    XrFoveatedRendererInputStatsFOVEART input =
        xr<XrFoveatedRendererInputStatsFOVEART>(XR_TYPE_FOVEATED_RENDERER_INPUT_STATS_FOVEART);
    XrFoveatedRendererReconstructionStatsFOVEART reconstruction =
        xr<XrFoveatedRendererReconstructionStatsFOVEART>(XR_TYPE_FOVEATED_RENDERER_RECONSTRUCTION_STATS_FOVEART);
  };
  Stats stats(XrFoveatedRendererFOVEART renderer) {
    Stats s;
    s.main.next = &s.input;
    s.input.next = &s.reconstruction;
    EXPECT_EQ(get_stats(renderer, &s.main), XR_SUCCESS);
    return s;
  }

  std::string log() const { return read_text(env_.root() / "layer.log"); }

  static constexpr uint32_t kSwapchainPx = 256;
  uint32_t swapchain_px = kSwapchainPx;
  const IsolatedEnv& env_;
  XrTestApp app;
  XrSpace space = XR_NULL_HANDLE;
  XrSwapchain swapchain = XR_NULL_HANDLE;
  PFN_xrCreateFoveatedRendererFOVEART create = nullptr;
  PFN_xrDestroyFoveatedRendererFOVEART destroy = nullptr;
  PFN_xrGetFoveatedRendererStatsFOVEART get_stats = nullptr;
};

// Small views build their tables in well under a second, also under sanitizers.
constexpr XrRect2Di kSmall{{0, 0}, {48, 40}};

std::string config(const IsolatedEnv& env, const std::string& extra = "") {
  return R"({"log_level": "debug", "threads": 2, "log_file": ")" + (env.root() / "layer.log").string() +
         R"(", "cache_dir": ")" + (env.root() / "tables").string() + "\"" + extra + "}";
}

TEST(LayerConformance, EndFrameWithNullInfoOrNullLayersIsTheRuntimesToJudge) {
  FOVEART_REQUIRE_RUNTIME();
  IsolatedEnv env;
  LayerApp a(env, config(env));
  a.start();
  const auto renderer = a.make_renderer();
  auto wait = xr<XrFrameWaitInfo>(XR_TYPE_FRAME_WAIT_INFO);
  auto state = xr<XrFrameState>(XR_TYPE_FRAME_STATE);
  ASSERT_EQ(xrWaitFrame(a.app.session, &wait, &state), XR_SUCCESS);
  auto begin = xr<XrFrameBeginInfo>(XR_TYPE_FRAME_BEGIN_INFO);
  ASSERT_EQ(xrBeginFrame(a.app.session, &begin), XR_SUCCESS);
  // Each goes down as sent and the runtime's answer comes back; the frame stays open.
  EXPECT_EQ(xrEndFrame(a.app.session, nullptr), XR_ERROR_VALIDATION_FAILURE);
  auto end = xr<XrFrameEndInfo>(XR_TYPE_FRAME_END_INFO);
  end.displayTime = state.predictedDisplayTime;
  end.environmentBlendMode = XR_ENVIRONMENT_BLEND_MODE_OPAQUE;
  end.layerCount = 1;
  end.layers = nullptr;
  EXPECT_EQ(xrEndFrame(a.app.session, &end), XR_ERROR_VALIDATION_FAILURE);
  const XrCompositionLayerBaseHeader* null_layer[] = {nullptr};
  end.layers = null_layer;
  EXPECT_EQ(xrEndFrame(a.app.session, &end), XR_ERROR_LAYER_INVALID);
  end.layerCount = 0;
  EXPECT_EQ(xrEndFrame(a.app.session, &end), XR_SUCCESS);
  EXPECT_EQ(a.stats(renderer).main.framesTraced, 0u);
}

TEST(LayerConformance, UnknownRendererHandleForwardsTheFrameUntraced) {
  FOVEART_REQUIRE_RUNTIME();
  IsolatedEnv env;
  LayerApp a(env, config(env, R"(, "wait_for_tables": true)"));
  a.start();
  const auto renderer = a.make_renderer();
  const auto unknown = reinterpret_cast<XrFoveatedRendererFOVEART>(uintptr_t{0xdead});
  EXPECT_EQ(a.frame(unknown, kSmall), XR_SUCCESS);
  const auto s = a.stats(renderer);
  EXPECT_EQ(s.main.framesTraced, 0u);
  EXPECT_EQ(s.main.framesFallback, 0u);
  EXPECT_EQ(a.get_stats(unknown, nullptr), XR_ERROR_HANDLE_INVALID);
  EXPECT_EQ(a.destroy(unknown), XR_ERROR_HANDLE_INVALID);
  // The same frame with the real renderer is traced: the unknown one was just ignored.
  EXPECT_EQ(a.frame(renderer, kSmall), XR_SUCCESS);
  EXPECT_EQ(a.stats(renderer).main.framesTraced, 1u);
}

// The app-recorded trace's entry points on a session whose device has no
// timelineSemaphore (the test app enables none) and a renderer without
// it: every bad call is an XrResult, nothing is traced, the frame goes on.
TEST(LayerConformance, AppRecordedTraceRefusesBadCallsWithXrResults) {
  FOVEART_REQUIRE_RUNTIME();
  IsolatedEnv env;
  LayerApp a(env, config(env, R"(, "wait_for_tables": true)"));
  a.start();
  const auto acquire = a.app.proc<PFN_xrAcquireFoveatedRayBatchFOVEART>("xrAcquireFoveatedRayBatchFOVEART");
  const auto release = a.app.proc<PFN_xrReleaseFoveatedRayBatchFOVEART>("xrReleaseFoveatedRayBatchFOVEART");
  ASSERT_TRUE(acquire && release);
  auto info = xr<XrFoveatedRendererCreateInfoFOVEART>(XR_TYPE_FOVEATED_RENDERER_CREATE_INFO_FOVEART);
  info.traceRays = &grey;
  auto app_trace = xr<XrFoveatedAppTraceInfoFOVEART>(XR_TYPE_FOVEATED_APP_TRACE_INFO_FOVEART);
  info.next = &app_trace;
  XrFoveatedRendererFOVEART refused = XR_NULL_HANDLE;
  EXPECT_EQ(a.create(a.app.session, &info, &refused), XR_ERROR_VALIDATION_FAILURE) << "no timelineSemaphore";
  const auto renderer = a.make_renderer();  // the callback alone
  const XrView view = xr<XrView>(XR_TYPE_VIEW);
  const XrExtent2Di size{64, 64};
  auto acquire_info = xr<XrFoveatedRayBatchAcquireInfoFOVEART>(XR_TYPE_FOVEATED_RAY_BATCH_ACQUIRE_INFO_FOVEART);
  acquire_info.viewCount = 1;
  acquire_info.views = &view;
  acquire_info.imageSizes = &size;
  XrFoveatedDeviceRayBatchFOVEART views[1] = {};
  auto batch = xr<XrFoveatedRayBatchFOVEART>(XR_TYPE_FOVEATED_RAY_BATCH_FOVEART);
  batch.viewCapacityInput = 1;
  batch.views = views;
  EXPECT_EQ(acquire(renderer, &acquire_info, &batch), XR_ERROR_VALIDATION_FAILURE) << "not an app-recorded renderer";
  EXPECT_EQ(acquire(renderer, nullptr, &batch), XR_ERROR_VALIDATION_FAILURE);
  EXPECT_EQ(acquire(renderer, &acquire_info, nullptr), XR_ERROR_VALIDATION_FAILURE);
  const auto unknown = reinterpret_cast<XrFoveatedRendererFOVEART>(uintptr_t{0xdead});
  EXPECT_EQ(acquire(unknown, &acquire_info, &batch), XR_ERROR_HANDLE_INVALID);
  EXPECT_EQ(release(unknown, 1), XR_ERROR_HANDLE_INVALID);
  EXPECT_EQ(release(renderer, 1), XR_ERROR_VALIDATION_FAILURE) << "never handed out";
  EXPECT_EQ(a.frame(renderer, kSmall), XR_SUCCESS);
  EXPECT_EQ(a.stats(renderer).main.framesTraced, 1u) << "the callback still traces";
}

TEST(LayerConformance, ThreeViewsAreForwardedForTheRuntimeToReject) {
  FOVEART_REQUIRE_RUNTIME();
  IsolatedEnv env;
  LayerApp a(env, config(env, R"(, "wait_for_tables": true)"));
  a.start();
  const auto renderer = a.make_renderer();
  EXPECT_EQ(a.frame(renderer, kSmall, 3), XR_ERROR_VALIDATION_FAILURE);  // the stereo runtime wants 2
  const auto s = a.stats(renderer);
  EXPECT_EQ(s.main.framesFallback, 1u) << "the third view is the app's";
  EXPECT_EQ(a.frame(renderer, kSmall, 2), XR_SUCCESS);
}

TEST(LayerConformance, AViewThatCannotBeTracedIsForwardedAsSentAndNotTraced) {
  FOVEART_REQUIRE_RUNTIME();
  IsolatedEnv env;
  LayerApp a(env, config(env, R"(, "wait_for_tables": true)"));
  a.start();
  const auto renderer = a.make_renderer();
  ASSERT_EQ(a.frame(renderer, kSmall), XR_SUCCESS);
  ASSERT_EQ(a.stats(renderer).main.framesTraced, 1u);
  // A position beyond any scene (Embree aborts on such a ray origin), a NaN one, and a field of
  // view turned inside out: the simulated runtime takes them, the layer does not trace them.
  const std::function<void(XrCompositionLayerProjectionView&)> spoil[] = {
      [](XrCompositionLayerProjectionView& v) { v.pose.position.x = 1e30f; },
      [](XrCompositionLayerProjectionView& v) { v.pose.position.y = std::numeric_limits<float>::quiet_NaN(); },
      [](XrCompositionLayerProjectionView& v) { std::swap(v.fov.angleLeft, v.fov.angleRight); }};
  for (const auto& edit : spoil) {
    EXPECT_EQ(a.frame(renderer, kSmall, 2, 0.7f, edit), XR_SUCCESS);
    const auto s = a.stats(renderer);
    EXPECT_NE(s.main.fallbackFlags & XR_FOVEATED_FALLBACK_INVALID_VIEW_BIT_FOVEART, 0u);
  }
  // A pose that is not a unit quaternion reaches the runtime as sent, which refuses it as without the layer.
  EXPECT_EQ(
      a.frame(renderer, kSmall, 2, 0.7f, [](XrCompositionLayerProjectionView& v) { v.pose.orientation.w = 2.0f; }),
      XR_ERROR_POSE_INVALID);
  const auto s = a.stats(renderer);
  EXPECT_EQ(s.main.framesTraced, 5u) << "the first frame, and the other eye of each spoiled one";
  EXPECT_EQ(s.main.framesFallback, 4u) << "one eye of each of the four spoiled frames";
  EXPECT_EQ(count_of(a.log(), "its view cannot be traced"), 1u) << a.log();
  EXPECT_NE(a.log().find("position (1e+30, 0, 0) m is not finite or lies beyond 1e+09 m"), std::string::npos)
      << a.log();
  ASSERT_EQ(a.frame(renderer, kSmall), XR_SUCCESS);
  EXPECT_EQ(a.stats(renderer).main.fallbackFlags & XR_FOVEATED_FALLBACK_INVALID_VIEW_BIT_FOVEART, 0u)
      << "the flag is the frame's";
}

TEST(LayerConformance, RectOutsideTheSwapchainIsForwardedAsSentAndNotTraced) {
  FOVEART_REQUIRE_RUNTIME();
  IsolatedEnv env;
  LayerApp a(env, config(env, R"(, "wait_for_tables": true)"));
  a.start();
  const auto renderer = a.make_renderer();
  const XrRect2Di outside{{LayerApp::kSwapchainPx - 20, 0}, {48, 40}};
  // Rewritten to the layer's own swapchain this would pass; the runtime must see the app's error.
  EXPECT_EQ(a.frame(renderer, outside), XR_ERROR_SWAPCHAIN_RECT_INVALID);
  const XrRect2Di wrapping{{INT32_MAX - 4, 0}, {48, 40}};  // offset + extent wraps int32
  EXPECT_EQ(a.frame(renderer, wrapping), XR_ERROR_SWAPCHAIN_RECT_INVALID);
  const auto s = a.stats(renderer);
  EXPECT_EQ(s.input.invalidImageRectViews, 4u);
  EXPECT_NE(s.main.fallbackFlags & XR_FOVEATED_FALLBACK_INVALID_IMAGE_RECT_BIT_FOVEART, 0u);
  EXPECT_EQ(s.main.framesTraced, 0u);
  EXPECT_EQ(count_of(a.log(), "lies outside its swapchain image"), 1u) << a.log();
  EXPECT_EQ(a.frame(renderer, kSmall), XR_SUCCESS);
  EXPECT_EQ(a.stats(renderer).main.framesTraced, 1u);
}

TEST(LayerConformance, NoRgba8FormatOfferedFallsBackWithoutFailingTheFrame) {
  FOVEART_REQUIRE_RUNTIME();
  IsolatedEnv env;
  IsolatedEnv::set("FOVEART_SIM_FORMATS", "float");
  LayerApp a(env, config(env, R"(, "wait_for_tables": true)"));
  a.start();
  const auto renderer = a.make_renderer();
  EXPECT_EQ(a.frame(renderer, kSmall), XR_SUCCESS);
  EXPECT_EQ(a.frame(renderer, kSmall), XR_SUCCESS);
  const auto s = a.stats(renderer);
  EXPECT_EQ(s.main.framesTraced, 0u);
  EXPECT_EQ(s.main.framesFallback, 4u);
  EXPECT_NE(s.main.fallbackFlags & XR_FOVEATED_FALLBACK_UPLOAD_FAILED_BIT_FOVEART, 0u);
  EXPECT_NE(a.log().find("no RGBA8 swapchain format"), std::string::npos) << a.log();
  ::unsetenv("FOVEART_SIM_FORMATS");
}

TEST(LayerConformance, TwoSessionsInSequence) {
  FOVEART_REQUIRE_RUNTIME();
  IsolatedEnv env;
  LayerApp a(env, config(env, R"(, "wait_for_tables": true)"));
  a.start();
  const auto first = a.make_renderer();
  EXPECT_EQ(a.frame(first, kSmall), XR_SUCCESS);
  EXPECT_EQ(a.stats(first).main.framesTraced, 1u);
  a.end_session();  // destroys the first renderer with its session
  EXPECT_EQ(a.get_stats(first, nullptr), XR_ERROR_HANDLE_INVALID);
  a.start_session();
  const auto second = a.make_renderer();
  EXPECT_NE(second, first);
  EXPECT_EQ(a.frame(first, kSmall), XR_SUCCESS) << "a stale renderer handle is ignored";
  EXPECT_EQ(a.frame(second, kSmall), XR_SUCCESS);
  const auto s = a.stats(second);
  EXPECT_EQ(s.main.framesTraced, 1u);
  EXPECT_EQ(s.input.cacheFilesRejected, 0u) << "the first session's cache files load";
}

TEST(LayerConformance, DestroyingARendererCancelsItsTableBuild) {
  FOVEART_REQUIRE_RUNTIME();
  IsolatedEnv env;
  LayerApp a(env, config(env));
  a.swapchain_px = 1280;
  a.start();
  const auto renderer = a.make_renderer();
  // A FOVE-sized eye (seconds of table build); the frame only queues it.
  EXPECT_EQ(a.frame(renderer, {{0, 0}, {1280, 1280}}, 2, 0.83f), XR_SUCCESS);
  EXPECT_NE(a.stats(renderer).main.fallbackFlags & XR_FOVEATED_FALLBACK_WARMING_UP_BIT_FOVEART, 0u);
  // Let the builder get into the build (it may not have; either way nothing may be finished).
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  EXPECT_EQ(a.destroy(renderer), XR_SUCCESS);
  // Cancelled, not finished: the interpolation table (the build's last file) was never written.
  std::size_t interpolation_files = 0;
  if (fs::exists(env.root() / "tables")) {
    for (const auto& e : fs::directory_iterator(env.root() / "tables")) {
      interpolation_files += e.path().filename().string().starts_with("interp") ? 1 : 0;
    }
  }
  EXPECT_EQ(interpolation_files, 0u);
  EXPECT_EQ(a.log().find("cannot build"), std::string::npos) << "a cancel is not a failure: " << a.log();
}

TEST(LayerConformance, ViewSizeChangingEveryFrameKeepsTableMemoryBounded) {
  FOVEART_REQUIRE_RUNTIME();
  IsolatedEnv env;
  LayerApp a(env, config(env));
  a.start();
  const auto renderer = a.make_renderer();
  constexpr int kFrames = 1000;
  for (int i = 0; i < kFrames; ++i) {
    const XrRect2Di rect{{0, 0}, {32 + i % 200, 24 + i / 200}};  // 1000 different sizes
    ASSERT_EQ(a.frame(renderer, rect), XR_SUCCESS) << "frame " << i;
  }
  const auto s = a.stats(renderer);
  EXPECT_LE(s.input.tableSetsResident, 4u);
  EXPECT_EQ(s.input.tableSetsEvicted + s.input.tableSetsResident, std::uint64_t{kFrames});
  EXPECT_EQ(count_of(a.log(), "least recently used first"), 1u);
}

// The GPU path (lavapipe) through the lifetime events a session sees: a view
// size change (new layer swapchain, GPU eye buffers and uploaded tables), the
// renderer destroyed and created again, and a config that forbids the GPU.
TEST(LayerConformance, GpuPathSurvivesResizeAndRendererRecreation) {
  FOVEART_REQUIRE_RUNTIME();
  IsolatedEnv env;
  LayerApp a(env, config(env, R"(, "wait_for_tables": true, "reconstruction": "gpu")"));
  a.start();
  auto renderer = a.make_renderer();
  for (const XrRect2Di rect : {kSmall, XrRect2Di{{0, 0}, {64, 48}}, kSmall}) {
    ASSERT_EQ(a.frame(renderer, rect), XR_SUCCESS);
    const auto s = a.stats(renderer);
    EXPECT_EQ(s.reconstruction.path, XR_FOVEATED_RECONSTRUCTION_PATH_GPU_FOVEART);
    EXPECT_EQ(s.main.fallbackFlags & ~XR_FOVEATED_FALLBACK_FIXED_FOVEATION_BIT_FOVEART, 0u);  // no gaze here
  }
  EXPECT_EQ(a.stats(renderer).main.framesFallback, 0u);
  EXPECT_EQ(a.stats(renderer).main.framesTraced, 3u);
  EXPECT_EQ(a.destroy(renderer), XR_SUCCESS);
  renderer = a.make_renderer();
  ASSERT_EQ(a.frame(renderer, kSmall), XR_SUCCESS);
  const auto s = a.stats(renderer);
  EXPECT_EQ(s.main.framesTraced, 1u);
  EXPECT_EQ(s.reconstruction.path, XR_FOVEATED_RECONSTRUCTION_PATH_GPU_FOVEART);
  EXPECT_EQ(s.reconstruction.gpuFallbacks, 0u);
  EXPECT_NE(a.log().find("reconstruction on the GPU"), std::string::npos) << a.log();
}

TEST(LayerConformance, ConfigCpuKeepsReconstructionOnTheCpu) {
  FOVEART_REQUIRE_RUNTIME();
  IsolatedEnv env;
  LayerApp a(env, config(env, R"(, "wait_for_tables": true, "reconstruction": "cpu")"));
  a.start();
  const auto renderer = a.make_renderer();
  ASSERT_EQ(a.frame(renderer, kSmall), XR_SUCCESS);
  const auto s = a.stats(renderer);
  EXPECT_EQ(s.main.framesTraced, 1u);
  EXPECT_EQ(s.reconstruction.path, XR_FOVEATED_RECONSTRUCTION_PATH_CPU_FOVEART);
  EXPECT_EQ(s.reconstruction.gpuGatherMs[0], 0.0f);
  EXPECT_NE(a.log().find("reconstruction on the CPU"), std::string::npos) << a.log();
}

// The render cache on the CPU path works, but its cost grows with the rays it keeps: the log
// says so once, and only there.
TEST(LayerConformance, TheRenderCacheOnTheCpuPathIsNamedSlowOnceInTheLog) {
  FOVEART_REQUIRE_RUNTIME();
  for (const char* reconstruction : {"cpu", "gpu"}) {
    SCOPED_TRACE(reconstruction);
    IsolatedEnv env;
    LayerApp a(env,
               config(env, std::string(R"(, "wait_for_tables": true, "reconstruction": ")") + reconstruction + "\""));
    a.start();
    const auto renderer = a.make_renderer(nullptr, false, XR_FOVEATED_TEMPORAL_RAYS_FOVEART);
    for (int f = 0; f < 2; ++f) ASSERT_EQ(a.frame(renderer, kSmall), XR_SUCCESS);
    EXPECT_EQ(a.stats(renderer).main.framesTraced, 2u);
    const std::size_t warnings = count_of(a.log(), "with reconstruction on the CPU: the render cache");
    EXPECT_EQ(warnings, std::string(reconstruction) == "cpu" ? 1u : 0u) << a.log();
  }
}

// An app whose VkInstance asks for Vulkan 1.0 may not be handed SPIR-V 1.3 on
// its device (the validation layer says "Invalid SPIR-V binary version 1.3
// for target environment SPIR-V 1.0"), whatever the device offers: even with
// "reconstruction": "gpu" the layer reconstructs on the CPU and says why.
TEST(LayerConformance, AVulkan10InstanceKeepsReconstructionOnTheCpu) {
  FOVEART_REQUIRE_RUNTIME();
  IsolatedEnv env;
  LayerApp a(env, config(env, R"(, "wait_for_tables": true, "reconstruction": "gpu")"));
  a.app.vulkan_api_version = VK_API_VERSION_1_0;
  a.start();
  const auto renderer = a.make_renderer();
  ASSERT_EQ(a.frame(renderer, kSmall), XR_SUCCESS);
  const auto s = a.stats(renderer);
  EXPECT_EQ(s.main.framesTraced, 1u);
  EXPECT_EQ(s.main.framesFallback, 0u);
  EXPECT_EQ(s.reconstruction.path, XR_FOVEATED_RECONSTRUCTION_PATH_CPU_FOVEART);
  EXPECT_NE(a.log().find("the app's Vulkan instance asked for Vulkan 1.0"), std::string::npos) << a.log();
}

// The layer's device work on the app's device, under the Vulkan validation layer
// with synchronization validation (the app enables it): not one error,
// with the app at Vulkan 1.1 (the GPU path through a resize and a new renderer)
// and at 1.0 (the CPU path: no SPIR-V 1.3 on a device used at 1.0).
class ValidatedLayerApp : public ::testing::TestWithParam<uint32_t> {};

TEST_P(ValidatedLayerApp, TheLayersDeviceWorkHasNoValidationMessages) {
  FOVEART_REQUIRE_RUNTIME();
  IsolatedEnv env;
  IsolatedEnv::set("VK_LAYER_PATH", "/usr/share/vulkan/explicit_layer.d");
  LayerApp a(env, config(env, R"(, "wait_for_tables": true, "reconstruction": "gpu")"));
  a.app.vulkan_api_version = GetParam();
  a.app.vulkan_validation = true;
  a.start();
  ASSERT_TRUE(a.app.validation.active()) << "the Vulkan validation layer is not installed or gives no messenger";
  const bool gpu = GetParam() >= VK_API_VERSION_1_1;
  auto renderer = a.make_renderer();
  for (const XrRect2Di rect : {kSmall, XrRect2Di{{0, 0}, {64, 48}}}) ASSERT_EQ(a.frame(renderer, rect), XR_SUCCESS);
  EXPECT_EQ(a.destroy(renderer), XR_SUCCESS);
  renderer = a.make_renderer();
  ASSERT_EQ(a.frame(renderer, kSmall), XR_SUCCESS);
  const auto s = a.stats(renderer);
  EXPECT_EQ(s.main.framesTraced, 1u);
  EXPECT_EQ(s.reconstruction.path,
            gpu ? XR_FOVEATED_RECONSTRUCTION_PATH_GPU_FOVEART : XR_FOVEATED_RECONSTRUCTION_PATH_CPU_FOVEART);
  EXPECT_EQ(a.destroy(renderer), XR_SUCCESS);
  a.end_session();
  ::unsetenv("VK_LAYER_PATH");
  for (const std::string& m : a.app.validation.errors()) ADD_FAILURE() << m;
}

INSTANTIATE_TEST_SUITE_P(VulkanVersions, ValidatedLayerApp, ::testing::Values(VK_API_VERSION_1_1, VK_API_VERSION_1_0),
                         [](const auto& version) { return version.param == VK_API_VERSION_1_0 ? "vulkan_1_0" : "vulkan_1_1"; });

TEST(LayerInputs, UnwritableCacheIsLoggedOnceAndCounted) {
  FOVEART_REQUIRE_RUNTIME();
  IsolatedEnv env;
  std::ofstream(env.root() / "a_file") << "x";
  const std::string cache = (env.root() / "a_file" / "tables").string();  // under a regular file
  LayerApp a(env, R"({"log_level": "debug", "wait_for_tables": true, "log_file": ")" +
                      (env.root() / "layer.log").string() + R"(", "cache_dir": ")" + cache + R"("})");
  a.start();
  const auto renderer = a.make_renderer();
  EXPECT_EQ(a.frame(renderer, kSmall), XR_SUCCESS);
  const auto s = a.stats(renderer);
  EXPECT_EQ(s.main.framesTraced, 1u) << "tables built without a cache";
  EXPECT_GE(s.input.cacheFailures, 3u) << "point set, neighbour table, interpolation table";
  EXPECT_EQ(count_of(a.log(), "(logged once, counted in the stats)"), 1u) << a.log();
  EXPECT_NE(a.log().find("cache not written"), std::string::npos) << a.log();
}

TEST(LayerInputs, RejectedCacheFileIsLoggedOnceAndCounted) {
  FOVEART_REQUIRE_RUNTIME();
  IsolatedEnv env;
  LayerApp a(env, config(env, R"(, "wait_for_tables": true)"));
  a.start();
  const auto first = a.make_renderer();
  EXPECT_EQ(a.frame(first, kSmall), XR_SUCCESS);
  EXPECT_EQ(a.destroy(first), XR_SUCCESS);
  // Damage every cache file's last byte: checksums fail.
  int damaged = 0;
  for (const auto& e : fs::directory_iterator(env.root() / "tables")) {
    std::fstream f(e.path(), std::ios::in | std::ios::out | std::ios::binary);
    f.seekg(-1, std::ios::end);
    const char c = static_cast<char>(f.get() ^ 0x5a);
    f.seekp(-1, std::ios::end);
    f.put(c);
    ++damaged;
  }
  ASSERT_GE(damaged, 2);
  const auto second = a.make_renderer();
  EXPECT_EQ(a.frame(second, kSmall), XR_SUCCESS);
  const auto s = a.stats(second);
  EXPECT_EQ(s.main.framesTraced, 1u);
  EXPECT_GE(s.input.cacheFilesRejected, 1u);
  EXPECT_EQ(count_of(a.log(), "logged once, counted in the stats"), 1u) << a.log();
  EXPECT_NE(a.log().find("cache file rejected"), std::string::npos) << a.log();
}

TEST(LayerInputs, FailedTableBuildIsReportedNotWarmingUpForever) {
  FOVEART_REQUIRE_RUNTIME();
  IsolatedEnv env;
  LayerApp a(env, config(env, R"(, "wait_for_tables": true)"));
  a.start();
  const auto renderer = a.make_renderer();
  // A field of view of 0.2 microradians is a view, but its point set holds one point: too few for k.
  EXPECT_EQ(a.frame(renderer, kSmall, 2, 1e-7f), XR_SUCCESS);
  EXPECT_EQ(a.frame(renderer, kSmall, 2, 1e-7f), XR_SUCCESS);
  const auto s = a.stats(renderer);
  EXPECT_EQ(s.input.tableBuildsFailed, 1u);
  EXPECT_NE(s.main.fallbackFlags & XR_FOVEATED_FALLBACK_TABLES_FAILED_BIT_FOVEART, 0u);
  EXPECT_EQ(s.main.fallbackFlags & XR_FOVEATED_FALLBACK_WARMING_UP_BIT_FOVEART, 0u);
  EXPECT_EQ(count_of(a.log(), "cannot build the foveation tables"), 1u) << a.log();
}

// A trace whose valid gaze looks straight back (+z is forward in traces), for
// the runtime's eye tracker (XR_EXT_eye_gaze_interaction) and for the gaze provider.
fs::path backward_trace(const IsolatedEnv& env) {
  const fs::path trace = env.root() / "behind.csv";
  std::ofstream out(trace);
  out << "device_time_us,frame_id,valid,gaze_x,gaze_y,gaze_z\n";
  for (int i = 0; i < 600; ++i) out << i * 8333 << "," << i << ",1,0,0,-1\n";
  return trace;
}

void expect_backward_gaze_flagged(LayerApp& a, const LayerApp::Stats& s) {
  EXPECT_GE(s.input.gazeBehindViews, 2u);
  EXPECT_NE(s.main.fallbackFlags & XR_FOVEATED_FALLBACK_FIXED_FOVEATION_BIT_FOVEART, 0u);
  EXPECT_EQ(s.main.gazePixel[0].x, 24.0f) << "the lens centre of a symmetric 48x40 view";
  EXPECT_EQ(s.main.gazePixel[0].y, 20.0f);
  EXPECT_EQ(count_of(a.log(), "the gaze points backwards"), 1u) << a.log();
}

TEST(LayerInputs, BackwardGazeFromTheRuntimeIsFlaggedAndLoggedOnce) {
  FOVEART_REQUIRE_RUNTIME();
  IsolatedEnv env;
  IsolatedEnv::set("FOVEART_SIM_GAZE", backward_trace(env));
  LayerApp a(env, config(env, R"(, "wait_for_tables": true)"));
  a.start();
  const auto renderer = a.make_renderer(nullptr, true);
  for (int i = 0; i < 3; ++i) ASSERT_EQ(a.frame(renderer, kSmall), XR_SUCCESS);
  const auto s = a.stats(renderer);
  EXPECT_EQ(s.main.gazeLostFrames, 0u) << "a backward gaze is a gaze, not a lost one";
  expect_backward_gaze_flagged(a, s);
  ::unsetenv("FOVEART_SIM_GAZE");
}

TEST(LayerInputs, BackwardGazeFromTheProviderIsFlaggedAndLoggedOnce) {
  FOVEART_REQUIRE_RUNTIME();
  IsolatedEnv env;
  const std::string spec = "replay:" + backward_trace(env).string();
  LayerApp a(env, config(env, R"(, "wait_for_tables": true)"));
  a.start();
  const auto renderer = a.make_renderer(spec.c_str());
  // Frames until the provider's first sample is in (it runs on the real clock, the runtime on a virtual one).
  LayerApp::Stats s;
  for (int i = 0; i < 1000 && s.input.gazeBehindViews == 0; ++i) {
    ASSERT_EQ(a.frame(renderer, kSmall), XR_SUCCESS);
    s = a.stats(renderer);
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  EXPECT_EQ(a.frame(renderer, kSmall), XR_SUCCESS);
  expect_backward_gaze_flagged(a, a.stats(renderer));
}

}  // namespace
}  // namespace foveart::layer::test
