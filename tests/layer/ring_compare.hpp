// Two 8-bit frames compared per ring of eccentricity around a gaze pixel, with
// the bounds gpu_engine_test.cpp states and justifies for "the GPU engine
// traced it instead of the CPU engine": per ring PSNR >= 45 dB, >= 99 % of
// pixels within one step and >= 99.5 % within two (a pixel's worst channel).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <vector>

#include "app_output.hpp"

namespace foveart::layer::test {

// Rings of eccentricity, degrees from the gaze direction: [edge[i], edge[i + 1]).
inline constexpr std::array<double, 6> kRingEdgesDeg = {0.0, 2.5, 5.0, 10.0, 20.0, 1000.0};
inline constexpr int kRings = int(kRingEdgesDeg.size()) - 1;
inline constexpr double kMinPsnrDb = 45.0;
inline constexpr double kMinWithin1 = 0.99;
inline constexpr double kMinWithin2 = 0.995;

struct RingDiff {
  std::size_t pixels = 0, within1 = 0, within2 = 0;
  int max_abs = 0;
  double sq = 0.0;  // sum of squared channel differences
  double psnr_db() const {
    if (pixels == 0) return std::numeric_limits<double>::infinity();
    const double mse = sq / double(pixels * 3);
    return mse == 0.0 ? std::numeric_limits<double>::infinity() : 10.0 * std::log10(255.0 * 255.0 / mse);
  }
  double share1() const { return pixels == 0 ? 1.0 : double(within1) / double(pixels); }
  double share2() const { return pixels == 0 ? 1.0 : double(within2) / double(pixels); }
  bool passes() const { return psnr_db() >= kMinPsnrDb && share1() >= kMinWithin1 && share2() >= kMinWithin2; }
};

// Unit view-space direction (+x right, +y up, -z forward) through pixel (x, y)
// (continuous, y down) of a width x height view with FOV angles {left, right, up, down}.
inline std::array<double, 3> pixel_direction(const std::vector<double>& fov, int width, int height, double x,
                                             double y) {
  const double tl = std::tan(fov[0]), tr = std::tan(fov[1]), tu = std::tan(fov[2]), td = std::tan(fov[3]);
  const double u = tl + (tr - tl) * x / width;
  const double v = tu - (tu - td) * y / height;
  const double n = std::sqrt(u * u + v * v + 1.0);
  return {u / n, v / n, -1.0 / n};
}

// a and b of the same size; (gaze_x, gaze_y): the gaze pixel as the layer reports it.
inline std::array<RingDiff, kRings> compare_rings(const Rgb8& a, const Rgb8& b, const std::vector<double>& fov,
                                                  double gaze_x, double gaze_y) {
  constexpr double kPi = 3.14159265358979323846;
  std::array<RingDiff, kRings> rings{};
  // The gaze pixel is a pixel centre's coordinate as the layer reports it; its direction:
  const auto g = pixel_direction(fov, a.width, a.height, gaze_x + 0.5, gaze_y + 0.5);
  for (int y = 0; y < a.height; ++y) {
    for (int x = 0; x < a.width; ++x) {
      const auto d = pixel_direction(fov, a.width, a.height, x + 0.5, y + 0.5);
      const double c = std::clamp(d[0] * g[0] + d[1] * g[1] + d[2] * g[2], -1.0, 1.0);
      const double deg = std::acos(c) * 180.0 / kPi;
      int r = 0;
      while (r + 1 < kRings && deg >= kRingEdgesDeg[r + 1]) ++r;
      RingDiff& ring = rings[r];
      const std::size_t p = std::size_t(y) * std::size_t(a.width) + std::size_t(x);
      int worst = 0;
      for (int ch = 0; ch < 3; ++ch) {
        const int u = a.rgb[p * 3 + ch], v = b.rgb[p * 3 + ch];
        ring.sq += double(u - v) * (u - v);
        worst = std::max(worst, std::abs(u - v));
      }
      ++ring.pixels;
      ring.within1 += worst <= 1;
      ring.within2 += worst <= 2;
      ring.max_abs = std::max(ring.max_abs, worst);
    }
  }
  return rings;
}

inline void print_rings(const char* what, const std::array<RingDiff, kRings>& rings) {
  for (int r = 0; r < kRings; ++r) {
    const RingDiff& d = rings[r];
    std::printf("%s ring %4.1f-%5.1f deg: %6zu px, PSNR %6.2f dB, within 1 step %7.3f %%, within 2 %7.3f %%, max %3d\n",
                what, kRingEdgesDeg[r], kRingEdgesDeg[r + 1], d.pixels, d.psnr_db(), 100.0 * d.share1(),
                100.0 * d.share2(), d.max_abs);
  }
}

}  // namespace foveart::layer::test
