// Rigid poses for spaces and views (GLM underneath, XrPosef at the API edge).
#pragma once

#include <glm/gtc/quaternion.hpp>
#include <glm/vec3.hpp>

#include "xr_includes.h"

namespace foveart::sim {

struct Pose {
  glm::quat orientation{1.0F, 0.0F, 0.0F, 0.0F};
  glm::vec3 position{0.0F};
};

inline Pose operator*(const Pose& a, const Pose& b) {
  return {a.orientation * b.orientation, a.position + a.orientation * b.position};
}

inline Pose inverse(const Pose& p) {
  const glm::quat q = glm::conjugate(p.orientation);
  return {q, -(q * p.position)};
}

inline Pose from_xr(const XrPosef& p) {
  return {
      glm::normalize(glm::quat(p.orientation.w, p.orientation.x, p.orientation.y, p.orientation.z)),
      glm::vec3(p.position.x, p.position.y, p.position.z)};
}

inline XrPosef to_xr(const Pose& p) {
  XrPosef out{};
  out.orientation = {p.orientation.x, p.orientation.y, p.orientation.z, p.orientation.w};
  out.position = {p.position.x, p.position.y, p.position.z};
  return out;
}

// A pose whose -Z axis points along unit direction dir (OpenXR gaze convention).
Pose look_along(const glm::vec3& dir);

// True when the quaternion has unit length within tolerance (spec: pose validation).
bool is_unit_quaternion(const XrQuaternionf& q);

}  // namespace foveart::sim
