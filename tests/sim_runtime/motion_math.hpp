// Units and angles the motion tests compare in.
#pragma once

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <glm/vec3.hpp>

#include <cmath>
#include <cstdint>

namespace foveart::sim::test {

inline int64_t ns(double seconds) { return std::llround(seconds * 1e9); }

// Degrees between two directions (atan2 of |a x b| and a . b: exact near 0, unlike acos).
inline double angle_deg(const glm::vec3& a, const glm::vec3& b) {
  const glm::dvec3 u(a), v(b);
  return glm::degrees(std::atan2(glm::length(glm::cross(u, v)), glm::dot(u, v)));
}

}  // namespace foveart::sim::test
