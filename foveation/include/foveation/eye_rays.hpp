// Eye rays: from an eye view (pose + asymmetric XrFovf-style frustum) and a
// screen position in pixels to a ray in tracking space, and back.
// Pure math (GLM), no I/O: shared by the sample engine, the tools and the layer.
#pragma once

#include <foveation/ray_trace.h>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <cmath>

namespace foveart::foveation {

// The tangent-space frustum of one eye: tan of the four XrFovf angles.
// View space is OpenXR's: +x right, +y up, -z forward.
struct EyeFrustum {
  float tan_left = -1.0f;   // tan(angle_left), negative
  float tan_right = 1.0f;   // tan(angle_right), positive
  float tan_up = 1.0f;      // tan(angle_up), positive
  float tan_down = -1.0f;   // tan(angle_down), negative
  float width_px = 1.0f;
  float height_px = 1.0f;
};

struct EyePose {
  glm::vec3 position_m{0.0f};
  glm::quat orientation{1.0f, 0.0f, 0.0f, 0.0f};  // glm::quat(w, x, y, z)
};

inline EyeFrustum eye_frustum(const FoveartEyeView& view) {
  return EyeFrustum{std::tan(view.angle_left_rad), std::tan(view.angle_right_rad),
                    std::tan(view.angle_up_rad),   std::tan(view.angle_down_rad),
                    static_cast<float>(view.width_px), static_cast<float>(view.height_px)};
}

inline EyePose eye_pose(const FoveartEyeView& view) {
  const float* q = view.orientation_xyzw;
  return EyePose{glm::vec3(view.position_m[0], view.position_m[1], view.position_m[2]),
                 glm::normalize(glm::quat(q[3], q[0], q[1], q[2]))};
}

// Unnormalised view-space direction through a screen position (pixels, origin
// at the top-left corner, y down): a pinhole on the plane z = -1.
inline glm::vec3 view_direction_unnormalised(const EyeFrustum& f, glm::vec2 sample_px) {
  const float sx = sample_px.x / f.width_px;   // 0 at left edge, 1 at right edge
  const float sy = sample_px.y / f.height_px;  // 0 at top edge, 1 at bottom edge
  return glm::vec3(f.tan_left + sx * (f.tan_right - f.tan_left),
                   f.tan_up + sy * (f.tan_down - f.tan_up), -1.0f);
}

// The affine map from a screen position to an unnormalised tracking-space
// direction (the rotation of view_direction_unnormalised, which is affine in
// the position), folded once per view: a ray then costs six multiply-adds and
// a normalisation instead of two divisions and a quaternion rotation. The
// batches of rays an engine traces are made with it; it agrees with the
// per-ray form below to float rounding (a unit test holds them within 1e-6).
struct ScreenRayMap {
  glm::vec3 top_left{0.0f, 0.0f, -1.0f};  // through screen position (0, 0)
  glm::vec3 per_px_right{0.0f};           // change per pixel right
  glm::vec3 per_px_down{0.0f};            // change per pixel down
};

inline ScreenRayMap screen_ray_map(const EyeFrustum& f, const EyePose& pose) {
  return ScreenRayMap{pose.orientation * glm::vec3(f.tan_left, f.tan_up, -1.0f),
                      pose.orientation * glm::vec3((f.tan_right - f.tan_left) / f.width_px, 0.0f, 0.0f),
                      pose.orientation * glm::vec3(0.0f, (f.tan_down - f.tan_up) / f.height_px, 0.0f)};
}

// Unit direction in tracking space through a screen position.
inline glm::vec3 eye_ray_direction(const ScreenRayMap& m, glm::vec2 sample_px) {
  return glm::normalize(m.top_left + sample_px.x * m.per_px_right + sample_px.y * m.per_px_down);
}

// The same for one ray of a view, rotated per ray as the shaders compute it
// (eye_rays.glsl), so that the ray cache anchors its rays bit for bit alike
// on the CPU and the GPU.
inline glm::vec3 eye_ray_direction(const EyeFrustum& f, const EyePose& pose, glm::vec2 sample_px) {
  return glm::normalize(pose.orientation * view_direction_unnormalised(f, sample_px));
}

// Inverse of eye_ray_direction: the screen position a tracking-space direction
// projects to. Returns false for directions at or behind the eye plane.
inline bool project_direction(const EyeFrustum& f, const EyePose& pose, glm::vec3 direction,
                              glm::vec2* out_sample_px) {
  const glm::vec3 d = glm::conjugate(pose.orientation) * direction;
  if (!(d.z < 0.0f)) return false;
  const float x = d.x / -d.z;
  const float y = d.y / -d.z;
  out_sample_px->x = (x - f.tan_left) / (f.tan_right - f.tan_left) * f.width_px;
  out_sample_px->y = (y - f.tan_up) / (f.tan_down - f.tan_up) * f.height_px;
  return true;
}

// The pixel a view's -z axis hits (the lens centre; not the image centre for an
// asymmetric frustum), rounded to whole pixels: where a frame without gaze foveates.
inline glm::vec2 lens_centre_px(const EyeFrustum& f) {
  glm::vec2 px{};
  project_direction(f, EyePose{}, glm::vec3(0.0f, 0.0f, -1.0f), &px);
  return glm::round(px);
}

// The foveation pixel of a view-space gaze direction, rounded to whole pixels
// (the layer and `fovea-eval motion` alike); false for a gaze that points
// backwards or 87 degrees or more off the view axis (it projects nowhere useful).
inline bool gaze_pixel(const EyeFrustum& f, glm::vec3 direction_view, glm::vec2* out_px) {
  if (!(direction_view.z < -0.05f)) return false;
  glm::vec2 px{};
  project_direction(f, EyePose{}, direction_view, &px);
  *out_px = glm::round(px);
  return true;
}

// A symmetric-or-not view filled in C struct form, e.g. for tools and tests.
inline FoveartEyeView make_eye_view(uint32_t eye_index, uint32_t width_px, uint32_t height_px,
                                    const EyePose& pose, float angle_left_rad,
                                    float angle_right_rad, float angle_up_rad,
                                    float angle_down_rad) {
  FoveartEyeView v{};
  v.type = FOVEART_TYPE_EYE_VIEW;
  v.size = sizeof(FoveartEyeView);
  v.eye_index = eye_index;
  v.width_px = width_px;
  v.height_px = height_px;
  v.position_m[0] = pose.position_m.x;
  v.position_m[1] = pose.position_m.y;
  v.position_m[2] = pose.position_m.z;
  v.orientation_xyzw[0] = pose.orientation.x;
  v.orientation_xyzw[1] = pose.orientation.y;
  v.orientation_xyzw[2] = pose.orientation.z;
  v.orientation_xyzw[3] = pose.orientation.w;
  v.angle_left_rad = angle_left_rad;
  v.angle_right_rad = angle_right_rad;
  v.angle_up_rad = angle_up_rad;
  v.angle_down_rad = angle_down_rad;
  return v;
}

}  // namespace foveart::foveation
