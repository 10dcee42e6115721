#include "foveation/eye_view_check.hpp"

#include <cmath>
#include <numbers>
#include <sstream>

namespace foveart::foveation {

std::string eye_view_problem(const FoveartEyeView& view) {
  const float* p = view.position_m;
  const float* q = view.orientation_xyzw;
  const float norm2 = q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3];
  const float left = view.angle_left_rad, right = view.angle_right_rad, up = view.angle_up_rad,
              down = view.angle_down_rad;
  const auto inside_half_turn = [](float angle_rad) { return std::abs(angle_rad) < 0.5f * std::numbers::pi_v<float>; };
  const bool empty = view.width_px == 0 || view.height_px == 0;
  const bool far = !traceable_position(glm::vec3(p[0], p[1], p[2]));
  const bool not_unit = !(std::abs(norm2 - 1.0f) <= kUnitQuaternionTolerance);
  const bool bad_angles =
      !(inside_half_turn(left) && inside_half_turn(right) && inside_half_turn(up) && inside_half_turn(down)) ||
      !(left < right && down < up);
  if (!(empty || far || not_unit || bad_angles)) return {};  // every batch of a frame asks: no stream then
  std::ostringstream problem;
  if (empty) {
    problem << "an empty image (" << view.width_px << "x" << view.height_px << ")";
  } else if (far) {
    problem << "position (" << p[0] << ", " << p[1] << ", " << p[2] << ") m is not finite or lies beyond "
            << kMaxPositionM << " m";
  } else if (not_unit) {
    problem << "orientation (" << q[0] << ", " << q[1] << ", " << q[2] << ", " << q[3]
            << ") is not a unit quaternion";
  } else {
    problem << "field of view (left " << left << ", right " << right << ", up " << up << ", down " << down
            << " rad) is not within (-pi/2, pi/2) with left < right and down < up";
  }
  return problem.str();
}

}  // namespace foveart::foveation
