// Whether a frame can be traced from an eye view at all: the one check that the
// layer (each submitted and acquired view) and the engines' batch reader share,
// with the position bound that the tools' --pose and the engines' scenes meet
// too, so that no engine is handed a view, ray or scene it cannot trace.
#pragma once

#include <cmath>
#include <string>

#include <glm/vec3.hpp>

#include "foveation/ray_trace.h"

namespace foveart::foveation {

// The farthest an eye or a ray origin may lie from the origin, in metres. No
// scene lies beyond it (a float position there is coarser than 100 m), and
// Embree asserts on ray origins past 1.8e18.
inline constexpr float kMaxPositionM = 1e9f;

// How far an orientation's squared norm may lie from 1 (OpenXR asks for a unit
// quaternion; the simulated runtime refuses a pose beyond this).
inline constexpr float kUnitQuaternionTolerance = 1e-3f;

// A position that is finite and within kMaxPositionM on every axis.
inline bool traceable_position(glm::vec3 position_m) {
  return std::abs(position_m.x) <= kMaxPositionM && std::abs(position_m.y) <= kMaxPositionM &&
         std::abs(position_m.z) <= kMaxPositionM;  // false for NaN as well
}

// "" for a view a frame can be traced from; else what is wrong with it, in
// words: an empty image, a position that is not finite or lies beyond
// kMaxPositionM, an orientation that is not a unit quaternion, or angles that
// are not finite, inside (-90°, 90°) and ordered (left < right, down < up).
std::string eye_view_problem(const FoveartEyeView& view);

}  // namespace foveart::foveation
