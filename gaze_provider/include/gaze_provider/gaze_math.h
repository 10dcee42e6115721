// Small vector helpers for gaze directions (inline: they run at 120 Hz per sample).
#pragma once

#include <cmath>
#include <initializer_list>
#include <numbers>

#include "gaze_provider/gaze_sample.h"

namespace foveart::gaze {

inline constexpr double kDegPerRad = 180.0 / std::numbers::pi;

inline double dot(const Vec3f& a, const Vec3f& b) noexcept {
  return double(a.x) * double(b.x) + double(a.y) * double(b.y) + double(a.z) * double(b.z);
}

inline double length(const Vec3f& v) noexcept { return std::sqrt(dot(v, v)); }

inline bool is_finite(const Vec3f& v) noexcept {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// Unit vector, or (0,0,1) when `v` is zero or not finite.
inline Vec3f normalized(const Vec3f& v) noexcept {
  const double len = length(v);
  if (!(len > 1e-12) || !std::isfinite(len)) return {0.0f, 0.0f, 1.0f};
  return {float(double(v.x) / len), float(double(v.y) / len), float(double(v.z) / len)};
}

// Angle between two directions in degrees (atan2 form: accurate for tiny angles).
inline double angle_between_deg(const Vec3f& a, const Vec3f& b) noexcept {
  const double ax = a.x, ay = a.y, az = a.z, bx = b.x, by = b.y, bz = b.z;
  const double cx = ay * bz - az * by;
  const double cy = az * bx - ax * bz;
  const double cz = ax * by - ay * bx;
  return std::atan2(std::sqrt(cx * cx + cy * cy + cz * cz), dot(a, b)) * kDegPerRad;
}

struct YawPitchDeg {
  double yaw_deg = 0.0;
  double pitch_deg = 0.0;
};

inline YawPitchDeg to_yaw_pitch_deg(const Vec3f& d) noexcept {
  return {std::atan2(double(d.x), double(d.z)) * kDegPerRad,
          std::atan2(double(d.y), std::hypot(double(d.x), double(d.z))) * kDegPerRad};
}

inline Vec3f from_yaw_pitch_deg(double yaw_deg, double pitch_deg) noexcept {
  const double yaw = yaw_deg / kDegPerRad;
  const double pitch = pitch_deg / kDegPerRad;
  return {float(std::cos(pitch) * std::sin(yaw)), float(std::sin(pitch)),
          float(std::cos(pitch) * std::cos(yaw))};
}

// Moves both eyes' valid directions by the yaw/pitch change that took the combined
// direction from `from` to `to`: smoothing and prediction act on the combined gaze, and
// the eyes follow it, keeping their vergence.
inline void follow_combined(EyeGaze& left, EyeGaze& right, const Vec3f& from, const Vec3f& to) noexcept {
  const YawPitchDeg a = to_yaw_pitch_deg(from), b = to_yaw_pitch_deg(to);
  for (EyeGaze* e : {&left, &right}) {
    if (!e->valid) continue;
    const YawPitchDeg d = to_yaw_pitch_deg(e->direction);
    e->direction = from_yaw_pitch_deg(d.yaw_deg + (b.yaw_deg - a.yaw_deg), d.pitch_deg + (b.pitch_deg - a.pitch_deg));
  }
}

}  // namespace foveart::gaze
