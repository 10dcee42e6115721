// Pixel <-> ray math of one eye's image, for an XrView-style pose and
// asymmetric frustum. Pixel (0,0) is the top-left corner, x right, y down;
// the view looks down -z, y up (OpenXR view space).
#pragma once

#include <cmath>

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <openxr/openxr.h>

namespace foveart::layer {

struct EyeFrustum {
  float tan_left = -1, tan_right = 1, tan_up = 1, tan_down = -1;
  float width_px = 1, height_px = 1;

  static EyeFrustum from(const XrFovf& fov, float width_px, float height_px) {
    return {std::tan(fov.angleLeft), std::tan(fov.angleRight), std::tan(fov.angleUp), std::tan(fov.angleDown),
            width_px, height_px};
  }

  // View-space direction (unit) through screen position p.
  glm::vec3 direction_view(glm::vec2 p_px) const {
    const float x = tan_left + (p_px.x / width_px) * (tan_right - tan_left);
    const float y = tan_up - (p_px.y / height_px) * (tan_up - tan_down);
    return glm::normalize(glm::vec3(x, y, -1.0f));
  }

  // Screen position where a view-space direction lands (must point forward, z < 0).
  glm::vec2 pixel_of(glm::vec3 d_view) const {
    const float x = d_view.x / -d_view.z;
    const float y = d_view.y / -d_view.z;
    return {width_px * (x - tan_left) / (tan_right - tan_left), height_px * (tan_up - y) / (tan_up - tan_down)};
  }

  // The lens centre: where the view's forward axis meets the image.
  glm::vec2 centre_px() const { return pixel_of(glm::vec3(0.0f, 0.0f, -1.0f)); }
};

inline glm::quat to_glm(const XrQuaternionf& q) { return glm::quat(q.w, q.x, q.y, q.z); }
inline glm::vec3 to_glm(const XrVector3f& v) { return glm::vec3(v.x, v.y, v.z); }

}  // namespace foveart::layer
