// The headset FoveaRT simulates and builds its foveation tables for, described once.
//
// Every part that needs a headset's geometry or rates reads a HeadsetDescription:
// the simulated OpenXR runtime (its views' FOV, eye offsets, recommended image size,
// frame period, gaze sample rate), the sample engine's eye views (fove_eye_view) and
// the foveation tables (display_preset("fove")). A second copy of these numbers is a
// bug: the tables would be built for one display while the runtime shows another.
//
// Header-only and allocation-free; no OpenXR or Vulkan types (docs/design.md).
#pragma once

#include <cmath>
#include <cstdint>
#include <numbers>
#include <string_view>

namespace foveart::foveation {

// One eye's field of view as OpenXR's XrFovf: angles from the view axis in radians,
// left and down negative for a view around its axis.
struct EyeFovRad {
  double left = 0.0;
  double right = 0.0;
  double up = 0.0;
  double down = 0.0;
};

// Per-eye symmetric FOV with square pixels: the horizontal FOV fixes tan(right), and
// one pixel spans the same tangent both ways, so tan(up) = tan(right) * height / width.
inline EyeFovRad symmetric_fov_square_pixels(int width_px, int height_px, double horizontal_fov_rad) {
  const double tan_right = std::tan(0.5 * horizontal_fov_rad);
  const double up = std::atan(tan_right * double(height_px) / double(width_px));
  return {-0.5 * horizontal_fov_rad, 0.5 * horizontal_fov_rad, up, -up};
}

struct HeadsetDescription {
  std::string_view name;
  int eye_width_px = 0;   // per eye
  int eye_height_px = 0;  // per eye
  EyeFovRad eye_fov_rad{};  // both eyes (the views are parallel)
  double ipd_m = 0.0;       // distance between the two eyes' view origins
  double refresh_hz = 0.0;
  double eye_tracker_hz = 0.0;

  double horizontal_fov_rad() const { return eye_fov_rad.right - eye_fov_rad.left; }
  double vertical_fov_rad() const { return eye_fov_rad.up - eye_fov_rad.down; }
  // x of an eye's view origin in head space: eye 0 (left) at -IPD/2, eye 1 (right) at +IPD/2.
  double eye_offset_x_m(std::uint32_t eye_index) const { return eye_index == 0 ? -0.5 * ipd_m : 0.5 * ipd_m; }
  std::int64_t frame_period_ns() const { return std::llround(1e9 / refresh_hz); }
  std::int64_t gaze_period_ns() const { return std::llround(1e9 / eye_tracker_hz); }
};

// FOVE 0 (docs/design.md "Numbers to keep at hand"): 2560x1440 OLED, i.e. 1280x1440
// per eye, 70 Hz, ~95 deg field of view taken as each eye's horizontal FOV (as the
// foveation preset always had it), 120 Hz eye tracking, 64 mm IPD. The vertical FOV
// follows from square pixels: 2 atan(tan 47.5 deg * 1440 / 1280) = 101.7 deg.
inline HeadsetDescription fove0() {
  constexpr int kWidthPx = 1280, kHeightPx = 1440;
  constexpr double kHorizontalFovRad = 95.0 * std::numbers::pi / 180.0;
  HeadsetDescription d;
  d.name = "FOVE 0";
  d.eye_width_px = kWidthPx;
  d.eye_height_px = kHeightPx;
  d.eye_fov_rad = symmetric_fov_square_pixels(kWidthPx, kHeightPx, kHorizontalFovRad);
  d.ipd_m = 0.064;
  d.refresh_hz = 70.0;
  d.eye_tracker_hz = 120.0;
  return d;
}

}  // namespace foveart::foveation
