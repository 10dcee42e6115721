#include "foveation/history_reprojection.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>

#include <glm/geometric.hpp>

#include "foveation/eye_rays.hpp"

namespace foveart::foveation {

namespace {

// Catmull-Rom weights of the 4 taps around a sample at fraction t in [0, 1) past the second.
void catmull_rom_weights(float t, float w[4]) {
  const float t2 = t * t, t3 = t2 * t;
  w[0] = 0.5f * (-t3 + 2.0f * t2 - t);
  w[1] = 0.5f * (3.0f * t3 - 5.0f * t2 + 2.0f);
  w[2] = 0.5f * (-3.0f * t3 + 4.0f * t2 + t);
  w[3] = 0.5f * (t3 - t2);
}

// The history at pixel position s (pixel centres at +0.5), clamped at the edges.
void sample_history(const ImageRgb& history, glm::vec2 s, HistorySampling sampling, float* out) {
  const int hw = history.width_px, hh = history.height_px;
  const float fx = s.x - 0.5f, fy = s.y - 0.5f;
  const int x0 = int(std::floor(fx)), y0 = int(std::floor(fy));
  const float ax = fx - float(x0), ay = fy - float(y0);
  auto px = [&](int x, int y) { return history.at(std::clamp(x, 0, hw - 1), std::clamp(y, 0, hh - 1)); };
  const float* c00 = px(x0, y0);
  const float* c10 = px(x0 + 1, y0);
  const float* c01 = px(x0, y0 + 1);
  const float* c11 = px(x0 + 1, y0 + 1);
  if (sampling == HistorySampling::bilinear) {
    for (int c = 0; c < 3; ++c) {
      const float top = c00[c] + ax * (c10[c] - c00[c]);
      const float bottom = c01[c] + ax * (c11[c] - c01[c]);
      out[c] = top + ay * (bottom - top);
    }
    return;
  }
  float wx[4], wy[4];
  catmull_rom_weights(ax, wx);
  catmull_rom_weights(ay, wy);
  float sum[3] = {0.0f, 0.0f, 0.0f};
  for (int j = 0; j < 4; ++j) {
    for (int i = 0; i < 4; ++i) {
      const float* c = px(x0 - 1 + i, y0 - 1 + j);
      const float w = wx[i] * wy[j];
      for (int k = 0; k < 3; ++k) sum[k] += w * c[k];
    }
  }
  for (int k = 0; k < 3; ++k) {
    const float lo = std::min(std::min(c00[k], c10[k]), std::min(c01[k], c11[k]));
    const float hi = std::max(std::max(c00[k], c10[k]), std::max(c01[k], c11[k]));
    out[k] = std::min(std::max(sum[k], lo), hi);
  }
}

}  // namespace

ReprojectionStats reproject_history(const ImageRgb& history, const std::vector<float>& history_depth_m,
                                    const FoveartEyeView& history_view, const FoveartEyeView& view,
                                    const std::vector<float>& depth_m, ImageRgb& warped,
                                    std::vector<std::uint8_t>& valid, Executor& executor,
                                    HistorySampling sampling) {
  const int w = int(view.width_px), h = int(view.height_px);
  const int hw = history.width_px, hh = history.height_px;
  if (warped.width_px != w || warped.height_px != h) warped = ImageRgb(w, h);
  valid.assign(std::size_t(w) * std::size_t(h), 0);
  const EyeFrustum frustum = eye_frustum(view), history_frustum = eye_frustum(history_view);
  const EyePose pose = eye_pose(view), history_pose = eye_pose(history_view);
  const ScreenRayMap ray_map = screen_ray_map(frustum, pose);
  const bool has_depth = depth_m.size() == valid.size();
  const bool has_history_depth = history_depth_m.size() == std::size_t(hw) * std::size_t(hh);
  std::atomic<std::uint64_t> off_screen{0}, disoccluded{0}, with_depth{0};
  executor.parallel_chunks(std::size_t(h), 16, [&](std::size_t y0, std::size_t y1, unsigned) {
    std::uint64_t off = 0, occluded = 0, deep = 0;
    for (int y = int(y0); y < int(y1); ++y) {
      for (int x = 0; x < w; ++x) {
        const std::size_t p = std::size_t(y) * std::size_t(w) + std::size_t(x);
        const glm::vec3 d = eye_ray_direction(ray_map, {float(x) + 0.5f, float(y) + 0.5f});
        const float depth = has_depth ? depth_m[p] : NAN;
        const bool finite = std::isfinite(depth);
        glm::vec3 seen = d;  // direction from the previous eye
        float expected = INFINITY;  // distance of the surface from the previous eye
        if (finite) {
          const glm::vec3 point = pose.position_m + d * depth;
          seen = point - history_pose.position_m;
          expected = glm::length(seen);
          seen /= expected;
          ++deep;
        }
        glm::vec2 s;
        if (!project_direction(history_frustum, history_pose, seen, &s) || !(s.x >= 0.0f && s.x < float(hw)) ||
            !(s.y >= 0.0f && s.y < float(hh))) {
          ++off;
          continue;
        }
        const int nx = std::min(int(s.x), hw - 1), ny = std::min(int(s.y), hh - 1);
        if (has_history_depth && !std::isnan(depth)) {
          // The surface was there if its distance lies within the last depths of the
          // 3x3 pixels around (a pixel's depth is one jittered ray's: at an edge it
          // flips between the near and the far side from frame to frame).
          float lo = INFINITY, hi = -INFINITY;
          bool unknown = false;
          for (int dy = -1; dy <= 1; ++dy) {
            for (int dx = -1; dx <= 1; ++dx) {
              const int qx = std::clamp(nx + dx, 0, hw - 1), qy = std::clamp(ny + dy, 0, hh - 1);
              const float before = history_depth_m[std::size_t(qy) * std::size_t(hw) + std::size_t(qx)];
              if (std::isnan(before)) unknown = true;
              else lo = std::min(lo, before), hi = std::max(hi, before);
            }
          }
          const bool agree = unknown || (std::isinf(expected) ? std::isinf(hi)
                                                                : expected >= lo * (1.0f - kDisocclusionTolerance) &&
                                                                      expected <= hi * (1.0f + kDisocclusionTolerance));
          if (!agree) {
            ++occluded;
            continue;
          }
        }
        sample_history(history, s, sampling, warped.at(x, y));
        valid[p] = 1;
      }
    }
    off_screen += off;
    disoccluded += occluded;
    with_depth += deep;
  });
  return {off_screen.load(), disoccluded.load(), with_depth.load()};
}

}  // namespace foveart::foveation
