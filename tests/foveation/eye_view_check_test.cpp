// The one check of whether a frame can be traced from an eye view.
#include <gtest/gtest.h>

#include <limits>

#include "foveation/eye_rays.hpp"
#include "foveation/eye_view_check.hpp"

namespace foveart::foveation {
namespace {

FoveartEyeView good_view() {
  EyePose pose;
  pose.position_m = glm::vec3(0.03f, 1.6f, -2.0f);
  return make_eye_view(0, 64, 72, pose, -0.9f, 0.8f, 0.85f, -0.95f);
}

TEST(EyeViewCheck, AcceptsAnOrdinaryViewAndNamesWhatIsWrongWithABadOne) {
  EXPECT_EQ(eye_view_problem(good_view()), "");
  const float nan = std::numeric_limits<float>::quiet_NaN();
  struct Case {
    void (*spoil)(FoveartEyeView&, float nan);
    const char* says;
  };
  const Case cases[] = {
      {[](FoveartEyeView& v, float) { v.height_px = 0; }, "an empty image (64x0)"},
      {[](FoveartEyeView& v, float n) { v.position_m[2] = n; }, "is not finite or lies beyond 1e+09 m"},
      {[](FoveartEyeView& v, float) { v.position_m[0] = -1e30f; }, "position (-1e+30, 1.6, -2) m"},
      {[](FoveartEyeView& v, float) { v.orientation_xyzw[3] = 0.5f; }, "is not a unit quaternion"},
      {[](FoveartEyeView& v, float n) { v.orientation_xyzw[0] = n; }, "is not a unit quaternion"},
      {[](FoveartEyeView& v, float) { v.angle_left_rad = 0.9f; }, "left < right"},
      {[](FoveartEyeView& v, float) { v.angle_down_rad = 0.9f; }, "down < up"},
      {[](FoveartEyeView& v, float) { v.angle_right_rad = 1.58f; }, "within (-pi/2, pi/2)"},
      {[](FoveartEyeView& v, float n) { v.angle_up_rad = n; }, "field of view (left -0.9, right 0.8, up nan"},
  };
  for (const Case& c : cases) {
    FoveartEyeView v = good_view();
    c.spoil(v, nan);
    EXPECT_NE(eye_view_problem(v).find(c.says), std::string::npos) << eye_view_problem(v);
  }
  FoveartEyeView slightly_off = good_view();
  slightly_off.orientation_xyzw[3] = 1.0004f;  // within OpenXR's tolerance of a unit quaternion
  EXPECT_EQ(eye_view_problem(slightly_off), "");
}

}  // namespace
}  // namespace foveart::foveation
