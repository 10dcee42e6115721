// An OpenXR application against the simulated FOVE 0 through the real loader
// (libopenxr_loader): views, pacing, swapchain misuse, eye gaze, frame budget.
#include <gtest/gtest.h>
#include <stb_image.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>

#include "foveation/device.hpp"
#include "foveation/display_model.hpp"
#include "gaze_provider/gaze_math.h"
#include "gaze_provider/trace_csv.h"
#include "sim_runtime/sim_env.h"
#include "xr_test_app.h"

namespace foveart::sim::test {
namespace {

class SimRuntime : public ::testing::Test {
 protected:
  void SetUp() override { clear_sim_env(); }
};

XrSpace make_reference_space(XrSession session, XrReferenceSpaceType type) {
  XrReferenceSpaceCreateInfo info{};
  info.type = XR_TYPE_REFERENCE_SPACE_CREATE_INFO;
  info.referenceSpaceType = type;
  info.poseInReferenceSpace.orientation.w = 1.0F;
  XrSpace space = XR_NULL_HANDLE;
  EXPECT_EQ(xrCreateReferenceSpace(session, &info, &space), XR_SUCCESS);
  return space;
}

// The views are the one FOVE 0 description (foveation/device.hpp), the headset the
// foveation tables are built for: size, FOV angles, eye separation, frame period.
TEST_F(SimRuntime, ReportsTheFove0DescriptionsViewsFovAndIpd) {
  const foveation::HeadsetDescription fove = foveation::fove0();
  set_env({{"FOVEART_SIM_CLOCK", "virtual"}});
  XrTestApp app;
  ASSERT_EQ(app.create_instance(), XR_SUCCESS);
  uint32_t n = 0;
  ASSERT_EQ(
      xrEnumerateViewConfigurationViews(app.instance, app.system,
                                        XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO, 0, &n, nullptr),
      XR_SUCCESS);
  ASSERT_EQ(n, 2U);
  std::vector<XrViewConfigurationView> views(
      n, xr<XrViewConfigurationView>(XR_TYPE_VIEW_CONFIGURATION_VIEW));
  ASSERT_EQ(
      xrEnumerateViewConfigurationViews(
          app.instance, app.system, XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO, n, &n, views.data()),
      XR_SUCCESS);
  for (const auto& v : views) {
    EXPECT_EQ(v.recommendedImageRectWidth, static_cast<uint32_t>(fove.eye_width_px));
    EXPECT_EQ(v.recommendedImageRectHeight, static_cast<uint32_t>(fove.eye_height_px));
  }
  auto eye = xr<XrSystemEyeGazeInteractionPropertiesEXT>(
      XR_TYPE_SYSTEM_EYE_GAZE_INTERACTION_PROPERTIES_EXT);
  auto props = xr<XrSystemProperties>(XR_TYPE_SYSTEM_PROPERTIES, &eye);
  ASSERT_EQ(xrGetSystemProperties(app.instance, app.system, &props), XR_SUCCESS);
  EXPECT_EQ(eye.supportsEyeGazeInteraction, XR_TRUE);
  EXPECT_EQ(props.graphicsProperties.maxLayerCount, 16U);

  ASSERT_EQ(app.create_session(), XR_SUCCESS);
  ASSERT_TRUE(app.run_until_state(XR_SESSION_STATE_FOCUSED));
  XrSpace local = make_reference_space(app.session, XR_REFERENCE_SPACE_TYPE_LOCAL);
  auto locate = xr<XrViewLocateInfo>(XR_TYPE_VIEW_LOCATE_INFO);
  locate.viewConfigurationType = XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO;
  locate.displayTime = 2'000'000'000;
  locate.space = local;
  auto state = xr<XrViewState>(XR_TYPE_VIEW_STATE);
  std::vector<XrView> xr_views(2, xr<XrView>(XR_TYPE_VIEW));
  uint32_t count = 0;
  EXPECT_EQ(xrLocateViews(app.session, &locate, &state, 1, &count, xr_views.data()),
            XR_ERROR_SIZE_INSUFFICIENT);
  ASSERT_EQ(xrLocateViews(app.session, &locate, &state, 2, &count, xr_views.data()), XR_SUCCESS);
  EXPECT_EQ(count, 2U);
  EXPECT_NE(state.viewStateFlags & XR_VIEW_STATE_POSITION_VALID_BIT, 0U);
  const float ipd_m = xr_views[1].pose.position.x - xr_views[0].pose.position.x;
  EXPECT_NEAR(ipd_m, fove.ipd_m, 1e-6);
  EXPECT_NEAR(xr_views[0].pose.position.x, fove.eye_offset_x_m(0), 1e-6);
  for (const XrView& v : xr_views) {
    EXPECT_NEAR(v.fov.angleLeft, fove.eye_fov_rad.left, 1e-6);
    EXPECT_NEAR(v.fov.angleRight, fove.eye_fov_rad.right, 1e-6);
    EXPECT_NEAR(v.fov.angleUp, fove.eye_fov_rad.up, 1e-6);
    EXPECT_NEAR(v.fov.angleDown, fove.eye_fov_rad.down, 1e-6);
  }
  auto frame = xr<XrFrameState>(XR_TYPE_FRAME_STATE);
  ASSERT_EQ(app.empty_frame(&frame), XR_SUCCESS);
  EXPECT_EQ(frame.predictedDisplayPeriod, fove.frame_period_ns());
}

// The description itself: docs/design.md's FOVE 0 (1280x1440 per eye, 70 Hz, 95 deg,
// 120 Hz tracking) with the foveation preset's 64 mm; square pixels give the vertical FOV.
TEST(Fove0, DescriptionHasTheArchitecturesNumbersAndSquarePixels) {
  const foveation::HeadsetDescription fove = foveation::fove0();
  constexpr double kDegPerRad = 180.0 / M_PI;
  EXPECT_EQ(fove.eye_width_px, 1280);
  EXPECT_EQ(fove.eye_height_px, 1440);
  EXPECT_NEAR(fove.horizontal_fov_rad() * kDegPerRad, 95.0, 1e-9);
  EXPECT_NEAR(fove.eye_fov_rad.left, -fove.eye_fov_rad.right, 1e-12);
  EXPECT_NEAR(fove.eye_fov_rad.down, -fove.eye_fov_rad.up, 1e-12);
  EXPECT_NEAR(std::tan(fove.eye_fov_rad.up) / std::tan(fove.eye_fov_rad.right), 1440.0 / 1280.0, 1e-12);
  EXPECT_NEAR(fove.vertical_fov_rad() * kDegPerRad, 101.7, 0.05);
  EXPECT_DOUBLE_EQ(fove.ipd_m, 0.064);
  EXPECT_EQ(fove.frame_period_ns(), 14'285'714);
  EXPECT_EQ(fove.gaze_period_ns(), 8'333'333);
}

// display_preset("fove") (the foveation tables' display) is the same headset: the same
// pixels, and one viewing distance that spans both the horizontal and vertical FOV.
TEST(Fove0, FoveationPresetHasTheDescribedGeometry) {
  const foveation::HeadsetDescription fove = foveation::fove0();
  const auto preset = foveation::display_preset("fove");
  ASSERT_TRUE(preset.has_value());
  EXPECT_EQ(preset->width_px, fove.eye_width_px);
  EXPECT_EQ(preset->height_px, fove.eye_height_px);
  EXPECT_NEAR(preset->horizontal_fov_deg(), fove.horizontal_fov_rad() * 180.0 / M_PI, 1e-9);
  EXPECT_NEAR(0.5 * preset->width_px / preset->view_distance_px, std::tan(fove.eye_fov_rad.right), 1e-12);
  EXPECT_NEAR(0.5 * preset->height_px / preset->view_distance_px, std::tan(fove.eye_fov_rad.up), 1e-12);
}

// xrWaitFrame paces frames on the 70 Hz grid. On the virtual clock, which moves
// only when xrWaitFrame sleeps, every wait lands exactly on the next slot: each
// frame's predicted display time is one period after the last, none skipped,
// none repeated. (How punctually the real clock wakes is a measurement:
// bench/pacing_bench.cpp, SimClock70HzGrid.)
TEST_F(SimRuntime, WaitFramePacesAt70HzOnTheGrid) {
  set_env({{"FOVEART_SIM_CLOCK", "virtual"}});
  XrTestApp app;
  ASSERT_EQ(app.create_instance(), XR_SUCCESS);
  ASSERT_EQ(app.create_session(), XR_SUCCESS);
  ASSERT_TRUE(app.run_until_state(XR_SESSION_STATE_FOCUSED));
  constexpr int kFrames = 36;
  std::vector<XrTime> predicted;
  for (int i = 0; i < kFrames; ++i) {
    auto frame = xr<XrFrameState>(XR_TYPE_FRAME_STATE);
    ASSERT_EQ(app.empty_frame(&frame), XR_SUCCESS);
    predicted.push_back(frame.predictedDisplayTime);
    EXPECT_EQ(frame.predictedDisplayPeriod, 14'285'714);
  }
  for (size_t i = 1; i < predicted.size(); ++i) {
    EXPECT_EQ(predicted[i] - predicted[i - 1], 14'285'714) << "frame " << i << ": one slot of the 70 Hz grid";
  }
  // The grid starts where the session's first wait found the clock (kVirtualEpochNs).
  EXPECT_EQ((predicted.front() - env::kVirtualEpochNs) % 14'285'714, 0);
}

XrSwapchain make_swapchain(XrSession session, int64_t format, uint32_t w, uint32_t h,
                           XrResult* result) {
  auto info = xr<XrSwapchainCreateInfo>(XR_TYPE_SWAPCHAIN_CREATE_INFO);
  info.usageFlags = XR_SWAPCHAIN_USAGE_COLOR_ATTACHMENT_BIT | XR_SWAPCHAIN_USAGE_SAMPLED_BIT;
  info.format = format;
  info.sampleCount = 1;
  info.width = w;
  info.height = h;
  info.faceCount = 1;
  info.arraySize = 1;
  info.mipCount = 1;
  XrSwapchain sc = XR_NULL_HANDLE;
  *result = xrCreateSwapchain(session, &info, &sc);
  return sc;
}

TEST_F(SimRuntime, SwapchainMisuseReturnsTheSpecErrorCodes) {
  set_env({{"FOVEART_SIM_CLOCK", "virtual"}});
  XrTestApp app;
  ASSERT_EQ(app.create_instance(), XR_SUCCESS);
  ASSERT_EQ(app.create_session(), XR_SUCCESS);
  XrResult r = XR_SUCCESS;
  make_swapchain(app.session, VK_FORMAT_R32G32B32A32_SFLOAT, 64, 64, &r);
  EXPECT_EQ(r, XR_ERROR_SWAPCHAIN_FORMAT_UNSUPPORTED);
  XrSwapchain sc = make_swapchain(app.session, VK_FORMAT_R8G8B8A8_SRGB, 256, 128, &r);
  ASSERT_EQ(r, XR_SUCCESS);

  uint32_t n = 0;
  ASSERT_EQ(xrEnumerateSwapchainImages(sc, 0, &n, nullptr), XR_SUCCESS);
  ASSERT_GE(n, 2U);
  std::vector<XrSwapchainImageVulkan2KHR> images(
      n, xr<XrSwapchainImageVulkan2KHR>(XR_TYPE_SWAPCHAIN_IMAGE_VULKAN2_KHR));
  ASSERT_EQ(xrEnumerateSwapchainImages(
                sc, n, &n, reinterpret_cast<XrSwapchainImageBaseHeader*>(images.data())),
            XR_SUCCESS);
  for (const auto& img : images) EXPECT_NE(img.image, VK_NULL_HANDLE);

  auto wait = xr<XrSwapchainImageWaitInfo>(XR_TYPE_SWAPCHAIN_IMAGE_WAIT_INFO);
  wait.timeout = XR_INFINITE_DURATION;
  auto release = xr<XrSwapchainImageReleaseInfo>(XR_TYPE_SWAPCHAIN_IMAGE_RELEASE_INFO);
  auto acquire = xr<XrSwapchainImageAcquireInfo>(XR_TYPE_SWAPCHAIN_IMAGE_ACQUIRE_INFO);
  EXPECT_EQ(xrReleaseSwapchainImage(sc, &release),
            XR_ERROR_CALL_ORDER_INVALID);                                   // nothing acquired
  EXPECT_EQ(xrWaitSwapchainImage(sc, &wait), XR_ERROR_CALL_ORDER_INVALID);  // nothing acquired
  uint32_t index = 99;
  ASSERT_EQ(xrAcquireSwapchainImage(sc, &acquire, &index), XR_SUCCESS);
  EXPECT_LT(index, n);
  EXPECT_EQ(xrReleaseSwapchainImage(sc, &release), XR_ERROR_CALL_ORDER_INVALID);  // not waited
  ASSERT_EQ(xrWaitSwapchainImage(sc, &wait), XR_SUCCESS);
  EXPECT_EQ(xrWaitSwapchainImage(sc, &wait), XR_ERROR_CALL_ORDER_INVALID);  // waited twice
  ASSERT_EQ(xrReleaseSwapchainImage(sc, &release), XR_SUCCESS);
  // Acquiring every image is fine; one more is a call-order error.
  for (uint32_t i = 0; i < n; ++i)
    ASSERT_EQ(xrAcquireSwapchainImage(sc, &acquire, &index), XR_SUCCESS);
  EXPECT_EQ(xrAcquireSwapchainImage(sc, &acquire, &index), XR_ERROR_CALL_ORDER_INVALID);

  // Frame loop misuse.
  EXPECT_EQ(xrBeginFrame(app.session, nullptr), XR_ERROR_SESSION_NOT_RUNNING);
  ASSERT_TRUE(app.run_until_state(XR_SESSION_STATE_FOCUSED));
  auto begin = xr<XrFrameBeginInfo>(XR_TYPE_FRAME_BEGIN_INFO);
  EXPECT_EQ(xrBeginFrame(app.session, &begin), XR_ERROR_CALL_ORDER_INVALID);  // no xrWaitFrame
  auto end = xr<XrFrameEndInfo>(XR_TYPE_FRAME_END_INFO);
  end.displayTime = 1;
  end.environmentBlendMode = XR_ENVIRONMENT_BLEND_MODE_OPAQUE;
  EXPECT_EQ(xrEndFrame(app.session, &end), XR_ERROR_CALL_ORDER_INVALID);  // no xrBeginFrame

  auto frame = xr<XrFrameState>(XR_TYPE_FRAME_STATE);
  auto wait_frame = xr<XrFrameWaitInfo>(XR_TYPE_FRAME_WAIT_INFO);
  ASSERT_EQ(xrWaitFrame(app.session, &wait_frame, &frame), XR_SUCCESS);
  ASSERT_EQ(xrBeginFrame(app.session, &begin), XR_SUCCESS);
  XrSwapchain fresh = make_swapchain(app.session, VK_FORMAT_R8G8B8A8_SRGB, 256, 128, &r);
  ASSERT_EQ(r, XR_SUCCESS);
  XrSpace local = make_reference_space(app.session, XR_REFERENCE_SPACE_TYPE_LOCAL);
  std::vector<XrCompositionLayerProjectionView> views(
      2, xr<XrCompositionLayerProjectionView>(XR_TYPE_COMPOSITION_LAYER_PROJECTION_VIEW));
  for (auto& v : views) {
    v.pose.orientation.w = 1.0F;
    v.subImage.swapchain = fresh;
    v.subImage.imageRect = {{0, 0}, {256, 128}};
  }
  auto layer = xr<XrCompositionLayerProjection>(XR_TYPE_COMPOSITION_LAYER_PROJECTION);
  layer.space = local;
  layer.viewCount = 2;
  layer.views = views.data();
  const XrCompositionLayerBaseHeader* layers[] = {
      reinterpret_cast<XrCompositionLayerBaseHeader*>(&layer)};
  end.displayTime = frame.predictedDisplayTime;
  end.layerCount = 1;
  end.layers = layers;
  EXPECT_EQ(xrEndFrame(app.session, &end), XR_ERROR_LAYER_INVALID);  // swapchain never released
  for (auto& v : views) v.subImage.swapchain = sc;
  views[1].subImage.imageRect = {{128, 0}, {256, 128}};
  EXPECT_EQ(xrEndFrame(app.session, &end), XR_ERROR_SWAPCHAIN_RECT_INVALID);
  views[1].subImage.imageRect = {{0, 0}, {256, 128}};
  layer.viewCount = 1;
  EXPECT_EQ(xrEndFrame(app.session, &end), XR_ERROR_VALIDATION_FAILURE);  // stereo needs 2 views
  layer.viewCount = 2;
  end.environmentBlendMode = XR_ENVIRONMENT_BLEND_MODE_ADDITIVE;
  EXPECT_EQ(xrEndFrame(app.session, &end), XR_ERROR_ENVIRONMENT_BLEND_MODE_UNSUPPORTED);
  end.environmentBlendMode = XR_ENVIRONMENT_BLEND_MODE_OPAQUE;
  EXPECT_EQ(xrEndFrame(app.session, &end), XR_SUCCESS);
  EXPECT_EQ(xrDestroySwapchain(fresh), XR_SUCCESS);
  EXPECT_EQ(xrDestroySwapchain(fresh), XR_ERROR_HANDLE_INVALID);
  EXPECT_EQ(xrDestroySwapchain(sc), XR_SUCCESS);
}

// Eye gaze: the pose action bound to /user/eyes_ext/input/gaze_ext/pose returns
// the recorded trace's direction, stamped with the sample's time.
TEST_F(SimRuntime, EyeGazeActionReturnsTheRecordedGazeWithItsSampleTime) {
  const std::string dir = fresh_dir("gaze");
  const std::string trace = dir + "/trace.csv";
  {
    // The gaze provider's writer (gaze-diag's recorder), head space +z forward: 120 Hz
    // samples that turn 20 deg right and 10 deg up at 100 ms.
    std::ofstream out(trace);
    gaze::TraceWriter writer(out);
    for (int i = 0; i < 240; ++i) {
      gaze::GazeSample s;
      s.device_time_ns = (7000 + i * 8333LL) * 1000;
      s.frame_id = static_cast<uint64_t>(i);
      s.valid = true;
      s.eye_state = gaze::EyeState::open;
      s.confidence = 0.9F;
      s.combined_direction = (i * 8333 >= 100000) ? gaze::from_yaw_pitch_deg(20.0, 10.0) : gaze::Vec3f{0, 0, 1};
      writer.write(s);
    }
    ASSERT_TRUE(writer.ok());
  }
  set_env({{"FOVEART_SIM_CLOCK", "virtual"}, {"FOVEART_SIM_GAZE", trace}});
  XrTestApp app;
  ASSERT_EQ(app.create_instance(), XR_SUCCESS);
  ASSERT_EQ(app.create_session(), XR_SUCCESS);
  GazeActions g = make_gaze_actions(app);
  XrSpace view = make_reference_space(app.session, XR_REFERENCE_SPACE_TYPE_VIEW);
  ASSERT_TRUE(app.run_until_state(XR_SESSION_STATE_FOCUSED));
  EXPECT_TRUE(app.interaction_profile_changed);

  XrPath eyes = XR_NULL_PATH;
  ASSERT_EQ(xrStringToPath(app.instance, "/user/eyes_ext", &eyes), XR_SUCCESS);
  auto profile = xr<XrInteractionProfileState>(XR_TYPE_INTERACTION_PROFILE_STATE);
  ASSERT_EQ(xrGetCurrentInteractionProfile(app.session, eyes, &profile), XR_SUCCESS);
  EXPECT_NE(profile.interactionProfile, XR_NULL_PATH);

  ASSERT_EQ(sync(app, g.set), XR_SUCCESS);
  auto get = xr<XrActionStateGetInfo>(XR_TYPE_ACTION_STATE_GET_INFO);
  get.action = g.gaze;
  auto pose_state = xr<XrActionStatePose>(XR_TYPE_ACTION_STATE_POSE);
  ASSERT_EQ(xrGetActionStatePose(app.session, &get, &pose_state), XR_SUCCESS);
  EXPECT_EQ(pose_state.isActive, XR_TRUE);
  auto wrong = xr<XrActionStateBoolean>(XR_TYPE_ACTION_STATE_BOOLEAN);
  EXPECT_EQ(xrGetActionStateBoolean(app.session, &get, &wrong), XR_ERROR_ACTION_TYPE_MISMATCH);

  const XrTime epoch = env::kVirtualEpochNs;
  struct Probe {
    XrTime at;
    XrTime sample;
    float azimuth_deg;    // right of straight ahead
    float elevation_deg;  // above
  };
  // Sample k sits at epoch + k * 8.333 ms (trace times minus the first row's).
  const Probe probes[] = {{epoch + 50'000'000, epoch + 6 * 8'333'000LL, 0.0F, 0.0F},
                          {epoch + 120'000'000, epoch + 14 * 8'333'000LL, 20.0F, 10.0F}};
  for (const Probe& p : probes) {
    auto sample_time = xr<XrEyeGazeSampleTimeEXT>(XR_TYPE_EYE_GAZE_SAMPLE_TIME_EXT);
    auto location = xr<XrSpaceLocation>(XR_TYPE_SPACE_LOCATION, &sample_time);
    ASSERT_EQ(xrLocateSpace(g.gaze_space, view, p.at, &location), XR_SUCCESS);
    ASSERT_NE(location.locationFlags & XR_SPACE_LOCATION_ORIENTATION_VALID_BIT, 0U);
    EXPECT_EQ(sample_time.time, p.sample);
    // -Z of the gaze pose, in VIEW space (OpenXR: -z forward, +x right, +y up).
    const XrQuaternionf q = location.pose.orientation;
    const float fx = -2.0F * (q.x * q.z + q.w * q.y);
    const float fy = -2.0F * (q.y * q.z - q.w * q.x);
    const float fz = -(1.0F - 2.0F * (q.x * q.x + q.y * q.y));
    EXPECT_LT(fz, 0.0F) << "the gaze looks forward, not backwards";
    const float azimuth = std::atan2(fx, -fz) * 180.0F / static_cast<float>(M_PI);
    const float elevation = std::atan2(fy, std::hypot(fx, fz)) * 180.0F / static_cast<float>(M_PI);
    EXPECT_NEAR(azimuth, p.azimuth_deg, 0.01F);
    EXPECT_NEAR(elevation, p.elevation_deg, 0.01F);
  }
}

TEST_F(SimRuntime, EyeTrackingSwitchedOffLeavesGazeInactive) {
  set_env({{"FOVEART_SIM_CLOCK", "virtual"}, {"FOVEART_SIM_EYE_TRACKING", "0"}});
  XrTestApp app;
  ASSERT_EQ(app.create_instance(), XR_SUCCESS);
  auto eye = xr<XrSystemEyeGazeInteractionPropertiesEXT>(
      XR_TYPE_SYSTEM_EYE_GAZE_INTERACTION_PROPERTIES_EXT);
  auto props = xr<XrSystemProperties>(XR_TYPE_SYSTEM_PROPERTIES, &eye);
  ASSERT_EQ(xrGetSystemProperties(app.instance, app.system, &props), XR_SUCCESS);
  EXPECT_EQ(eye.supportsEyeGazeInteraction, XR_FALSE);
  ASSERT_EQ(app.create_session(), XR_SUCCESS);
  GazeActions g = make_gaze_actions(app);
  XrSpace view = make_reference_space(app.session, XR_REFERENCE_SPACE_TYPE_VIEW);
  ASSERT_TRUE(app.run_until_state(XR_SESSION_STATE_FOCUSED));
  ASSERT_EQ(sync(app, g.set), XR_SUCCESS);
  auto get = xr<XrActionStateGetInfo>(XR_TYPE_ACTION_STATE_GET_INFO);
  get.action = g.gaze;
  auto pose_state = xr<XrActionStatePose>(XR_TYPE_ACTION_STATE_POSE);
  ASSERT_EQ(xrGetActionStatePose(app.session, &get, &pose_state), XR_SUCCESS);
  EXPECT_EQ(pose_state.isActive, XR_FALSE);
  auto location = xr<XrSpaceLocation>(XR_TYPE_SPACE_LOCATION);
  ASSERT_EQ(xrLocateSpace(g.gaze_space, view, env::kVirtualEpochNs + 50'000'000, &location),
            XR_SUCCESS);
  EXPECT_EQ(location.locationFlags, 0U);
}

TEST_F(SimRuntime, SessionAsksToExitAfterTheFrameBudget) {
  set_env({{"FOVEART_SIM_CLOCK", "virtual"}, {"FOVEART_SIM_FRAMES", "5"}});
  XrTestApp app;
  ASSERT_EQ(app.create_instance(), XR_SUCCESS);
  ASSERT_EQ(app.create_session(), XR_SUCCESS);
  int frames = 0;
  for (int i = 0; i < 50 && app.state != XR_SESSION_STATE_EXITING; ++i) {
    app.drain_events();
    if (app.state == XR_SESSION_STATE_FOCUSED || app.state == XR_SESSION_STATE_READY ||
        app.state == XR_SESSION_STATE_VISIBLE || app.state == XR_SESSION_STATE_SYNCHRONIZED) {
      ASSERT_EQ(app.empty_frame(), XR_SUCCESS);
      ++frames;
    }
  }
  ASSERT_EQ(app.state, XR_SESSION_STATE_EXITING);
  EXPECT_EQ(frames, 5);
  const std::vector<XrSessionState> expected{
      XR_SESSION_STATE_IDLE,         XR_SESSION_STATE_READY,    XR_SESSION_STATE_SYNCHRONIZED,
      XR_SESSION_STATE_VISIBLE,      XR_SESSION_STATE_FOCUSED,  XR_SESSION_STATE_VISIBLE,
      XR_SESSION_STATE_SYNCHRONIZED, XR_SESSION_STATE_STOPPING, XR_SESSION_STATE_IDLE,
      XR_SESSION_STATE_EXITING};
  EXPECT_EQ(app.states, expected);
  auto frame = xr<XrFrameState>(XR_TYPE_FRAME_STATE);
  EXPECT_EQ(xrWaitFrame(app.session, nullptr, &frame), XR_ERROR_SESSION_NOT_RUNNING);
}

TEST_F(SimRuntime, BadConfigurationFailsInstanceCreation) {
  const std::string dir = fresh_dir("bad");
  { std::ofstream(dir + "/bad.csv") << "time,x,y\n1,2,3\n"; }
  for (const auto& vars :
       std::vector<std::map<std::string, std::string>>{{{"FOVEART_SIM_GAZE", dir + "/bad.csv"}},
                                                       {{"FOVEART_SIM_FRAMES", "-3"}},
                                                       {{"FOVEART_SIM_CLOCK", "fast"}}}) {
    clear_sim_env();
    set_env(vars);
    XrTestApp app;
    EXPECT_EQ(app.create_instance(), XR_ERROR_INITIALIZATION_FAILED) << vars.begin()->first;
  }
}

}  // namespace
}  // namespace foveart::sim::test

namespace foveart::sim::test {
namespace {

// Fills the acquired image with one colour on the app's queue, as an app would render.
void clear_image(XrTestApp& app, VkImage image, const VkClearColorValue& colour) {
  VkQueue queue = VK_NULL_HANDLE;
  vkGetDeviceQueue(app.vk_device, app.queue_family, 0, &queue);
  VkCommandPoolCreateInfo pool_info{};
  pool_info.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO;
  pool_info.queueFamilyIndex = app.queue_family;
  VkCommandPool pool = VK_NULL_HANDLE;
  ASSERT_EQ(vkCreateCommandPool(app.vk_device, &pool_info, nullptr, &pool), VK_SUCCESS);
  VkCommandBufferAllocateInfo alloc{};
  alloc.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO;
  alloc.commandPool = pool;
  alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  alloc.commandBufferCount = 1;
  VkCommandBuffer cmd = VK_NULL_HANDLE;
  ASSERT_EQ(vkAllocateCommandBuffers(app.vk_device, &alloc, &cmd), VK_SUCCESS);
  VkCommandBufferBeginInfo begin{};
  begin.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO;
  vkBeginCommandBuffer(cmd, &begin);
  const VkImageSubresourceRange range{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
  VkImageMemoryBarrier barrier{};
  barrier.sType = VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER;
  barrier.srcAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
  barrier.dstAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
  barrier.oldLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;  // as the runtime hands it out
  barrier.newLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
  barrier.srcQueueFamilyIndex = barrier.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  barrier.image = image;
  barrier.subresourceRange = range;
  vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT,
                       VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 0, nullptr, 0, nullptr, 1, &barrier);
  vkCmdClearColorImage(cmd, image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &colour, 1, &range);
  barrier.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
  barrier.dstAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
  barrier.oldLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
  barrier.newLayout =
      VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;  // the layout the spec wants at release
  vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT,
                       VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT, 0, 0, nullptr, 0, nullptr, 1,
                       &barrier);
  vkEndCommandBuffer(cmd);
  VkSubmitInfo submit{};
  submit.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO;
  submit.commandBufferCount = 1;
  submit.pCommandBuffers = &cmd;
  ASSERT_EQ(vkQueueSubmit(queue, 1, &submit, VK_NULL_HANDLE), VK_SUCCESS);
  // No wait here: the runtime's readback is ordered after this on the same queue.
  vkQueueWaitIdle(queue);  // only so the pool can be destroyed now
  vkDestroyCommandPool(app.vk_device, pool, nullptr);
}

TEST_F(SimRuntime, CaptureWritesEveryProjectionLayerViewInItsColours) {
  const std::string capture = fresh_dir("capture");
  set_env({{"FOVEART_SIM_CLOCK", "virtual"}, {"FOVEART_SIM_CAPTURE_DIR", capture}});
  XrTestApp app;
  ASSERT_EQ(app.create_instance(), XR_SUCCESS);
  ASSERT_EQ(app.create_session(), XR_SUCCESS);
  ASSERT_TRUE(app.run_until_state(XR_SESSION_STATE_FOCUSED));  // frame 0 is an empty frame
  XrSpace local = make_reference_space(app.session, XR_REFERENCE_SPACE_TYPE_LOCAL);

  // Layer 0 in RGBA, layer 1 in BGRA (checks the channel swizzle).
  const int64_t formats[] = {VK_FORMAT_R8G8B8A8_UNORM, VK_FORMAT_B8G8R8A8_UNORM};
  const VkClearColorValue colours[] = {{{1.0F, 0.0F, 0.0F, 1.0F}}, {{0.0F, 0.0F, 1.0F, 1.0F}}};
  XrSwapchain swapchains[2]{};
  for (int l = 0; l < 2; ++l) {
    auto info = xr<XrSwapchainCreateInfo>(XR_TYPE_SWAPCHAIN_CREATE_INFO);
    info.usageFlags = XR_SWAPCHAIN_USAGE_COLOR_ATTACHMENT_BIT | XR_SWAPCHAIN_USAGE_TRANSFER_DST_BIT;
    info.format = formats[l];
    info.sampleCount = info.faceCount = info.arraySize = info.mipCount = 1;
    info.width = 64;
    info.height = 32;
    ASSERT_EQ(xrCreateSwapchain(app.session, &info, &swapchains[l]), XR_SUCCESS);
  }
  XrFrameState frame = xr<XrFrameState>(XR_TYPE_FRAME_STATE);
  ASSERT_EQ(xrWaitFrame(app.session, nullptr, &frame), XR_SUCCESS);
  ASSERT_EQ(xrBeginFrame(app.session, nullptr), XR_SUCCESS);
  for (int l = 0; l < 2; ++l) {
    uint32_t n = 0;
    ASSERT_EQ(xrEnumerateSwapchainImages(swapchains[l], 0, &n, nullptr), XR_SUCCESS);
    std::vector<XrSwapchainImageVulkan2KHR> images(
        n, xr<XrSwapchainImageVulkan2KHR>(XR_TYPE_SWAPCHAIN_IMAGE_VULKAN2_KHR));
    ASSERT_EQ(
        xrEnumerateSwapchainImages(swapchains[l], n, &n,
                                   reinterpret_cast<XrSwapchainImageBaseHeader*>(images.data())),
        XR_SUCCESS);
    uint32_t index = 0;
    ASSERT_EQ(xrAcquireSwapchainImage(swapchains[l], nullptr, &index), XR_SUCCESS);
    auto wait = xr<XrSwapchainImageWaitInfo>(XR_TYPE_SWAPCHAIN_IMAGE_WAIT_INFO);
    wait.timeout = XR_INFINITE_DURATION;
    ASSERT_EQ(xrWaitSwapchainImage(swapchains[l], &wait), XR_SUCCESS);
    clear_image(app, images[index].image, colours[l]);
    ASSERT_EQ(xrReleaseSwapchainImage(swapchains[l], nullptr), XR_SUCCESS);
  }
  std::vector<XrCompositionLayerProjectionView> views[2];
  XrCompositionLayerProjection layers[2];
  const XrCompositionLayerBaseHeader* headers[2];
  for (int l = 0; l < 2; ++l) {
    views[l].assign(
        2, xr<XrCompositionLayerProjectionView>(XR_TYPE_COMPOSITION_LAYER_PROJECTION_VIEW));
    for (auto& v : views[l]) {
      v.pose.orientation.w = 1.0F;
      v.subImage.swapchain = swapchains[l];
      v.subImage.imageRect = {{0, 0}, {64, 32}};
    }
    layers[l] = xr<XrCompositionLayerProjection>(XR_TYPE_COMPOSITION_LAYER_PROJECTION);
    layers[l].space = local;
    layers[l].viewCount = 2;
    layers[l].views = views[l].data();
    headers[l] = reinterpret_cast<const XrCompositionLayerBaseHeader*>(&layers[l]);
  }
  auto end = xr<XrFrameEndInfo>(XR_TYPE_FRAME_END_INFO);
  end.displayTime = frame.predictedDisplayTime;
  end.environmentBlendMode = XR_ENVIRONMENT_BLEND_MODE_OPAQUE;
  end.layerCount = 2;
  end.layers = headers;
  ASSERT_EQ(xrEndFrame(app.session, &end), XR_SUCCESS);

  const std::string frame_name = "frame_000001";
  const std::pair<std::string, std::array<int, 3>> expected[] = {
      {frame_name + "_left.png", {255, 0, 0}},
      {frame_name + "_right.png", {255, 0, 0}},
      {frame_name + "_layer1_left.png", {0, 0, 255}},
      {frame_name + "_layer1_right.png", {0, 0, 255}}};
  for (const auto& [name, rgb] : expected) {
    int w = 0, h = 0, comp = 0;
    unsigned char* data = stbi_load((capture + "/" + name).c_str(), &w, &h, &comp, 3);
    ASSERT_NE(data, nullptr) << name;
    EXPECT_EQ(w, 64);
    EXPECT_EQ(h, 32);
    const size_t mid =
        (static_cast<size_t>(h / 2) * static_cast<size_t>(w) + static_cast<size_t>(w / 2)) * 3;
    EXPECT_EQ(data[mid + 0], rgb[0]) << name;
    EXPECT_EQ(data[mid + 1], rgb[1]) << name;
    EXPECT_EQ(data[mid + 2], rgb[2]) << name;
    stbi_image_free(data);
  }
  for (XrSwapchain sc : swapchains) EXPECT_EQ(xrDestroySwapchain(sc), XR_SUCCESS);
}

}  // namespace
}  // namespace foveart::sim::test

namespace foveart::sim::test {
namespace {

TEST_F(SimRuntime, OlderVulkanEnableWorksAndUnenabledExtensionsAreUnsupported) {
  const char* ext[] = {XR_KHR_VULKAN_ENABLE_EXTENSION_NAME};
  auto info = xr<XrInstanceCreateInfo>(XR_TYPE_INSTANCE_CREATE_INFO);
  std::snprintf(info.applicationInfo.applicationName, XR_MAX_APPLICATION_NAME_SIZE, "v1");
  info.applicationInfo.apiVersion = XR_CURRENT_API_VERSION;
  info.enabledExtensionCount = 1;
  info.enabledExtensionNames = ext;
  XrInstance instance = XR_NULL_HANDLE;
  ASSERT_EQ(xrCreateInstance(&info, &instance), XR_SUCCESS);
  auto sys = xr<XrSystemGetInfo>(XR_TYPE_SYSTEM_GET_INFO);
  sys.formFactor = XR_FORM_FACTOR_HANDHELD_DISPLAY;
  XrSystemId system = XR_NULL_SYSTEM_ID;
  EXPECT_EQ(xrGetSystem(instance, &sys, &system), XR_ERROR_FORM_FACTOR_UNSUPPORTED);
  sys.formFactor = XR_FORM_FACTOR_HEAD_MOUNTED_DISPLAY;
  ASSERT_EQ(xrGetSystem(instance, &sys, &system), XR_SUCCESS);

  PFN_xrVoidFunction fn = nullptr;
  ASSERT_EQ(xrGetInstanceProcAddr(instance, "xrGetVulkanInstanceExtensionsKHR", &fn), XR_SUCCESS);
  auto get_ext = reinterpret_cast<PFN_xrGetVulkanInstanceExtensionsKHR>(fn);
  uint32_t n = 0;
  ASSERT_EQ(get_ext(instance, system, 0, &n, nullptr), XR_SUCCESS);
  EXPECT_EQ(n, 1U);  // the empty string: the runtime needs no Vulkan extensions
  ASSERT_EQ(xrGetInstanceProcAddr(instance, "xrGetVulkanGraphicsRequirementsKHR", &fn), XR_SUCCESS);
  auto req = xr<XrGraphicsRequirementsVulkanKHR>(XR_TYPE_GRAPHICS_REQUIREMENTS_VULKAN_KHR);
  ASSERT_EQ(reinterpret_cast<PFN_xrGetVulkanGraphicsRequirementsKHR>(fn)(instance, system, &req),
            XR_SUCCESS);
  EXPECT_LE(req.minApiVersionSupported, XR_MAKE_VERSION(1, 0, 0));

  // Not enabled: XR_KHR_vulkan_enable2, XR_KHR_convert_timespec_time.
  EXPECT_EQ(xrGetInstanceProcAddr(instance, "xrCreateVulkanInstanceKHR", &fn),
            XR_ERROR_FUNCTION_UNSUPPORTED);
  EXPECT_EQ(fn, nullptr);
  EXPECT_EQ(xrGetInstanceProcAddr(instance, "xrConvertTimespecTimeToTimeKHR", &fn),
            XR_ERROR_FUNCTION_UNSUPPORTED);
  EXPECT_EQ(xrDestroyInstance(instance), XR_SUCCESS);
}

}  // namespace
}  // namespace foveart::sim::test

namespace foveart::sim::test {
namespace {

TEST_F(SimRuntime, RequestExitSessionWalksDownToExiting) {
  set_env({{"FOVEART_SIM_CLOCK", "virtual"}});
  XrTestApp app;
  ASSERT_EQ(app.create_instance(), XR_SUCCESS);
  ASSERT_EQ(app.create_session(), XR_SUCCESS);
  EXPECT_EQ(xrRequestExitSession(app.session), XR_ERROR_SESSION_NOT_RUNNING);
  EXPECT_EQ(xrEndSession(app.session), XR_ERROR_SESSION_NOT_RUNNING);
  ASSERT_TRUE(app.run_until_state(XR_SESSION_STATE_FOCUSED));
  EXPECT_EQ(xrEndSession(app.session), XR_ERROR_SESSION_NOT_STOPPING);
  ASSERT_EQ(xrRequestExitSession(app.session), XR_SUCCESS);
  app.states.clear();
  ASSERT_TRUE(app.run_until_state(XR_SESSION_STATE_EXITING, 5));
  const std::vector<XrSessionState> expected{
      XR_SESSION_STATE_VISIBLE, XR_SESSION_STATE_SYNCHRONIZED, XR_SESSION_STATE_STOPPING,
      XR_SESSION_STATE_IDLE, XR_SESSION_STATE_EXITING};
  EXPECT_EQ(app.states, expected);
}

}  // namespace
}  // namespace foveart::sim::test
