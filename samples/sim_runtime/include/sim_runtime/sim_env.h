// Environment variables understood by the simulated FOVE 0 OpenXR runtime
// (libfoveart_sim_runtime.so, manifest <build>/manifests/foveart_sim_runtime.json).
//
// The runtime reads them once, in xrCreateInstance. A malformed value makes
// xrCreateInstance fail with XR_ERROR_INITIALIZATION_FAILED after a message on
// stderr that names the variable and the value (a motion file that cannot be read:
// XR_ERROR_RUNTIME_FAILURE, naming file, line and column). docs/sim_runtime.md has the details.
#pragma once

namespace foveart::sim::env {

// Frames the runtime shows before it asks the application to exit (sessions go
// FOCUSED -> VISIBLE -> SYNCHRONIZED -> STOPPING, then IDLE -> EXITING after
// xrEndSession). Counted in xrEndFrame calls. Unset or 0: no budget.
inline constexpr const char* kFrames = "FOVEART_SIM_FRAMES";
// "real" (default): xrWaitFrame sleeps to a 70 Hz grid of CLOCK_MONOTONIC.
// "virtual": time only moves when xrWaitFrame is called, by one 70 Hz period;
// nothing sleeps. XrTime starts at 1 s (1'000'000'000 ns) at xrCreateInstance.
inline constexpr const char* kClock = "FOVEART_SIM_CLOCK";
// Gaze trace in the gaze provider's CSV format (gaze_provider/trace_csv.h, as
// `gaze-diag stream --record` writes it: +z forward); unset: the built-in saccade script.
// Ignored under kMotion.
inline constexpr const char* kGaze = "FOVEART_SIM_GAZE";
// "0" turns eye tracking off: supportsEyeGazeInteraction is XR_FALSE and gaze
// actions stay inactive. Default "1".
inline constexpr const char* kEyeTracking = "FOVEART_SIM_EYE_TRACKING";
// "static" (default) or "sway": slow scripted head yaw of +-10 deg at 0.1 Hz.
// Ignored under kMotion.
inline constexpr const char* kHead = "FOVEART_SIM_HEAD";
// Scripted head and gaze motion (motion/scripted_motion.hpp): "builtin" (4 s:
// head turning 10-30 deg/s, fixations, a 12 deg saccade at 1.5 s, a 150 ms blink at
// 3.0 s) or the path of a motion CSV (time_s,qx,qy,qz,qw,px,py,pz,gx,gy,gz,valid[,saccade]).
// Drives the head pose (VIEW, xrLocateViews) and the eye gaze pose from the session's
// xrBeginSession on, looping; overrides FOVEART_SIM_HEAD and FOVEART_SIM_GAZE. A motion
// file that cannot be read fails xrCreateInstance with XR_ERROR_RUNTIME_FAILURE.
inline constexpr const char* kMotion = "FOVEART_SIM_MOTION";
// Seed of the built-in motion (default 1); ignored for a motion file.
inline constexpr const char* kMotionSeed = "FOVEART_SIM_MOTION_SEED";
// Folder for frame capture: frame_NNNNNN_left.png / _right.png per projection
// layer view (layers after the first: frame_NNNNNN_layerK_left.png) and frames.csv.
inline constexpr const char* kCaptureDir = "FOVEART_SIM_CAPTURE_DIR";
// Capture every N-th frame's PNGs (frames.csv always has every frame). Default 1.
inline constexpr const char* kCaptureEvery = "FOVEART_SIM_CAPTURE_EVERY";
// Colour swapchain formats offered: "8bit" (default: R8G8B8A8/B8G8R8A8, sRGB and
// UNORM) or "float" (R16G16B16A16_SFLOAT only, no 8-bit RGBA: for tests of apps
// and layers that need one). Depth formats are offered either way.
inline constexpr const char* kFormats = "FOVEART_SIM_FORMATS";
// 0 quiet, 1 info (default), 2 debug. Messages go to stderr prefixed "foveart-sim".
inline constexpr const char* kLog = "FOVEART_SIM_LOG";

// The headset's numbers (views, IPD, rates) are foveart::foveation::fove0()
// (foveation/device.hpp), the description the foveation tables are built for.
// XrTime of xrCreateInstance under FOVEART_SIM_CLOCK=virtual; gaze traces start here.
inline constexpr long long kVirtualEpochNs = 1'000'000'000;

}  // namespace foveart::sim::env
