// OpenXR types -> GLM and the engine callback's view (ray_trace.h). The
// pixel <-> ray math itself is foveation/eye_rays.hpp's.
#pragma once

#include <cstdint>

#include <glm/gtc/quaternion.hpp>
#include <glm/vec3.hpp>

#include <openxr/openxr.h>

#include "foveation/eye_rays.hpp"

namespace foveart::layer {

inline glm::quat to_glm(const XrQuaternionf& q) { return glm::quat(q.w, q.x, q.y, q.z); }
inline glm::vec3 to_glm(const XrVector3f& v) { return glm::vec3(v.x, v.y, v.z); }

// The view an app submitted (pose in the layer's space, XrFovf angles, image size).
inline FoveartEyeView eye_view_of(uint32_t eye_index, const XrPosef& pose, const XrFovf& fov, uint32_t width_px,
                                  uint32_t height_px) {
  foveation::EyePose p;
  p.position_m = to_glm(pose.position);
  p.orientation = to_glm(pose.orientation);
  return foveation::make_eye_view(eye_index, width_px, height_px, p, fov.angleLeft, fov.angleRight, fov.angleUp,
                                  fov.angleDown);
}

}  // namespace foveart::layer
