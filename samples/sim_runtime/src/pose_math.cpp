#include "pose_math.h"

#include <cmath>

#define GLM_ENABLE_EXPERIMENTAL
#include <glm/gtx/quaternion.hpp>

namespace foveart::sim {

Pose look_along(const glm::vec3& dir) {
  Pose p;
  p.orientation = glm::rotation(glm::vec3(0.0F, 0.0F, -1.0F), glm::normalize(dir));
  return p;
}

bool is_unit_quaternion(const XrQuaternionf& q) {
  const float n = q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w;
  return std::fabs(n - 1.0F) < 1e-3F;
}

}  // namespace foveart::sim
