// eye_rays.hpp: pinhole directions from XrFovf-style angles and back.
#include <foveation/eye_rays.hpp>

#include <glm/gtc/constants.hpp>
#include <gtest/gtest.h>

#include <cmath>

namespace fv = foveart::foveation;

namespace {

FoveartEyeView view_with(float left, float right, float up, float down, fv::EyePose pose = {}) {
  return fv::make_eye_view(0, 200, 100, pose, left, right, up, down);
}

void expect_near(glm::vec3 a, glm::vec3 b, float tol = 1e-5f) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
}

}  // namespace

TEST(EyeRays, CentreOfSymmetricFrustumLooksDownMinusZ) {
  const FoveartEyeView v = view_with(-0.7f, 0.7f, 0.5f, -0.5f);
  expect_near(fv::eye_ray_direction(fv::eye_frustum(v), fv::eye_pose(v), {100.0f, 50.0f}), {0, 0, -1});
}

TEST(EyeRays, EdgesFollowTheAsymmetricAngles) {
  const float left = -0.9f, right = 0.4f, up = 0.6f, down = -0.3f;
  const FoveartEyeView v = view_with(left, right, up, down);
  const fv::EyeFrustum f = fv::eye_frustum(v);
  const fv::EyePose p = fv::eye_pose(v);
  const glm::vec3 top_left = fv::eye_ray_direction(f, p, {0.0f, 0.0f});
  EXPECT_NEAR(std::atan2(top_left.x, -top_left.z), left, 1e-5f);
  EXPECT_NEAR(top_left.y / -top_left.z, std::tan(up), 1e-5f);
  const glm::vec3 bottom_right = fv::eye_ray_direction(f, p, {200.0f, 100.0f});
  EXPECT_NEAR(bottom_right.x / -bottom_right.z, std::tan(right), 1e-5f);
  EXPECT_NEAR(bottom_right.y / -bottom_right.z, std::tan(down), 1e-5f);
  EXPECT_NEAR(glm::length(bottom_right), 1.0f, 1e-6f);
}

TEST(EyeRays, OrientationRotatesTheRays) {
  fv::EyePose pose;  // yaw 90 degrees left: forward becomes -x
  pose.orientation = glm::angleAxis(glm::half_pi<float>(), glm::vec3(0, 1, 0));
  const FoveartEyeView v = view_with(-0.5f, 0.5f, 0.5f, -0.5f, pose);
  expect_near(fv::eye_ray_direction(fv::eye_frustum(v), fv::eye_pose(v), {100.0f, 50.0f}), {-1, 0, 0});
}

// The folded map is the rotated pinhole direction, at every screen position
// of a FOVE-sized asymmetric view under a tilted head.
TEST(EyeRays, ScreenRayMapIsTheRotatedPinhole) {
  fv::EyePose pose;
  pose.orientation = glm::normalize(glm::quat(0.8f, -0.2f, 0.5f, 0.25f));
  const FoveartEyeView v = fv::make_eye_view(0, 1280, 1440, pose, -0.9f, 0.75f, 0.85f, -0.95f);
  const fv::EyeFrustum f = fv::eye_frustum(v);
  const fv::EyePose p = fv::eye_pose(v);
  const fv::ScreenRayMap map = fv::screen_ray_map(f, p);
  for (float y = 0.0f; y <= 1440.0f; y += 37.3f)
    for (float x = 0.0f; x <= 1280.0f; x += 41.7f)
      expect_near(fv::eye_ray_direction(map, {x, y}),
                  glm::normalize(p.orientation * fv::view_direction_unnormalised(f, {x, y})), 1e-6f);
}

TEST(EyeRays, ProjectInvertsDirection) {
  fv::EyePose pose;
  pose.orientation = glm::normalize(glm::quat(0.9f, 0.1f, -0.3f, 0.2f));
  const FoveartEyeView v = view_with(-0.8f, 0.6f, 0.7f, -0.5f, pose);
  const fv::EyeFrustum f = fv::eye_frustum(v);
  const fv::EyePose p = fv::eye_pose(v);
  for (glm::vec2 px : {glm::vec2(3.5f, 7.25f), glm::vec2(150.0f, 90.0f), glm::vec2(199.0f, 0.5f)}) {
    glm::vec2 back;
    ASSERT_TRUE(fv::project_direction(f, p, fv::eye_ray_direction(f, p, px), &back));
    EXPECT_NEAR(back.x, px.x, 1e-3f);
    EXPECT_NEAR(back.y, px.y, 1e-3f);
  }
  glm::vec2 unused;
  EXPECT_FALSE(fv::project_direction(f, p, -fv::eye_ray_direction(f, p, {100.0f, 50.0f}), &unused));
}
