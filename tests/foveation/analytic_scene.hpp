// A scene with a closed-form answer for TAA reprojection tests: a striped far
// wall (z = -10 m, or at infinity for rotation-only tests) and a bright near
// bar (z = -1 m, 0.2 m wide) in front of it. Colour and depth of a ray, and a
// supersampled image of a view as the truth.
#pragma once

#include <cmath>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "foveation/eye_rays.hpp"
#include "foveation/image.hpp"

namespace foveart::foveation::test {

struct AnalyticScene {
  bool wall_at_infinity = false;  // colour by direction only: every depth +inf
  bool near_bar = true;
  float bar_x_m = 0.0f;

  // Colour and distance along the unit ray (o, d).
  glm::vec3 shade(glm::vec3 o, glm::vec3 d, float* depth_m) const {
    if (near_bar && d.z < 0.0f) {
      const float t = (-1.0f - o.z) / d.z;
      const glm::vec3 p = o + t * d;
      if (std::abs(p.x - bar_x_m) < 0.1f && std::abs(p.y - 1.6f) < 0.5f) {
        *depth_m = t;
        return {0.9f, 0.1f, 0.1f};
      }
    }
    if (wall_at_infinity || !(d.z < 0.0f)) {
      *depth_m = INFINITY;
      const float a = std::atan2(d.x, -d.z);
      return {0.5f + 0.4f * std::sin(40.0f * a), 0.5f + 0.4f * std::cos(25.0f * d.y), 0.3f};
    }
    const float t = (-10.0f - o.z) / d.z;
    const glm::vec3 p = o + t * d;
    *depth_m = t;
    return {0.5f + 0.4f * std::sin(6.0f * p.x), 0.5f + 0.4f * std::cos(4.0f * p.y), 0.3f};
  }

  // The view's image, n x n samples per pixel (n = 1: pixel centres), and its
  // per-pixel depth (pixel centres).
  ImageRgb render(const FoveartEyeView& view, int n, std::vector<float>* depth_m = nullptr) const {
    const EyeFrustum f = eye_frustum(view);
    const EyePose pose = eye_pose(view);
    ImageRgb img(int(view.width_px), int(view.height_px));
    if (depth_m != nullptr) depth_m->assign(img.pixel_count(), 0.0f);
    for (int y = 0; y < img.height_px; ++y) {
      for (int x = 0; x < img.width_px; ++x) {
        glm::vec3 sum(0.0f);
        for (int j = 0; j < n * n; ++j) {
          const glm::vec2 s(float(x) + (float(j % n) + 0.5f) / float(n), float(y) + (float(j / n) + 0.5f) / float(n));
          float depth = 0.0f;
          sum += shade(pose.position_m, eye_ray_direction(f, pose, s), &depth);
        }
        float* out = img.at(x, y);
        for (int c = 0; c < 3; ++c) out[c] = sum[c] / float(n * n);
        if (depth_m != nullptr) {
          float depth = 0.0f;
          shade(pose.position_m, eye_ray_direction(f, pose, {float(x) + 0.5f, float(y) + 0.5f}), &depth);
          (*depth_m)[std::size_t(y) * std::size_t(img.width_px) + std::size_t(x)] = depth;
        }
      }
    }
    return img;
  }
};

}  // namespace foveart::foveation::test
