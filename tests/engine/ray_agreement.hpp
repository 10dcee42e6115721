// Per-ray agreement of two engines' radiance and depth for the same rays, and
// its tolerances: gpu_tracer_test.cpp (GpuTracer against engine::Tracer),
// gpu_tracer_rt_test.cpp (the ray-tracing pipeline against the compute kernel),
// gpu_callback_adapter_test.cpp (the adapter against engine::Tracer).
#pragma once

#include <gtest/gtest.h>

#include <glm/vec4.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <vector>

namespace foveart::gpu_engine::testing {

// Agreement of two radiance/depth lists against a reference. A ray's error:
// the largest channel difference relative to the reference's brightest channel
// (+1e-3 so black stays absolute); its depth error: relative to the reference's
// depth, hit against miss counting as off.
//
// Tolerances, from what the engines do. GpuTracer's compute kernel on lavapipe
// against engine::Tracer (Embree), every scene and ray set of
// gpu_tracer_test.cpp and gpu_callback_adapter_test.cpp (4096 to 28800 rays
// each; lavapipe of Mesa 22.3 / LLVM 15, x86-64, 2-core VM): no ray sees
// another surface; the worst ray is off by 1.65e-3 (the 160x180 2-spp full
// render; 8.4e-4 the worst of the 4096-ray scenes), the worst depth by 1.6e-6
// relative. kRayTolerance is 3x the worst ray, kDepthTolerance 6x the worst
// depth: room for float differences on other machines (traversal order,
// Embree's rcp, fma), while a shading defect that moves a colour by 1 % fails.
// Textures are images the shaders decode and filter in float as the CPU engine
// (scene_textures.hpp): BoxTextured.gltf's worst ray is off by 6.1e-5, that of
// five 2048² textures (gpu_texture_test.cpp) by 5.6e-5. lavapipe's own sRGB
// decode would put rays 1.8e-2 off.
inline constexpr double kRayTolerance = 5e-3;
inline constexpr double kDepthTolerance = 1e-5;  // relative (absolute below 1 m)

struct Agreement {
  double within = 0.0;     // share of rays with error <= 1e-3 (reported)
  double max_error = 0.0;  // the worst ray's
  size_t worst_ray = 0;
  double mean_error = 0.0;
  size_t off = 0;          // rays with error above kRayTolerance
  double max_depth_error = 0.0;  // relative, over rays that hit (or miss) in both
  size_t depth_off = 0;    // rays whose hit/miss differs or whose depth is off by more than kDepthTolerance
  size_t n = 0;
};

inline Agreement compare(const std::vector<glm::vec4>& out, const std::vector<glm::vec4>& ref) {
  Agreement a;
  a.n = ref.size();
  size_t ok = 0;
  for (size_t i = 0; i < a.n; ++i) {
    const glm::vec4 g = out[i], c = ref[i];
    const float diff = std::max({std::fabs(g.r - c.r), std::fabs(g.g - c.g), std::fabs(g.b - c.b)});
    const double err = std::isfinite(diff) ? double(diff) / (double(std::max({c.r, c.g, c.b})) + 1e-3) : 1e30;
    if (err > a.max_error) {
      a.max_error = err;
      a.worst_ray = i;
    }
    a.mean_error += err;
    if (err <= 1e-3) ++ok;
    if (err > kRayTolerance) ++a.off;
    double depth_err = 0.0;
    if (std::isinf(c.w) || std::isinf(g.w)) {
      depth_err = std::isinf(c.w) && std::isinf(g.w) && (c.w > 0) == (g.w > 0) ? 0.0 : 1e30;
    } else if (std::isnan(c.w) || std::isnan(g.w)) {
      depth_err = std::isnan(c.w) && std::isnan(g.w) ? 0.0 : 1e30;
    } else {
      depth_err = std::fabs(double(g.w) - double(c.w)) / std::max(1.0, double(c.w));
    }
    if (depth_err < 1e30) a.max_depth_error = std::max(a.max_depth_error, depth_err);
    if (depth_err > kDepthTolerance) ++a.depth_off;
  }
  const double n = static_cast<double>(std::max<size_t>(a.n, 1));
  a.within = static_cast<double>(ok) / n;
  a.mean_error /= n;
  return a;
}

// Every ray within kRayTolerance and its depth within kDepthTolerance, but for
// at most `flipped_share` of the rays: those grazing an edge, which see another
// surface under another traversal (the ray-tracing pipeline against the compute
// kernel). 0 where the two agree ray for ray (the compute kernel against Embree).
inline void expect_agreement(const Agreement& a, const char* what, double flipped_share = 0.0) {
  std::printf("[ agreement ] %s: %zu samples, %.4f%% within 1e-3, mean error %.2e, worst ray %zu off by %.3g, "
              "%zu over %.1e; depth worst %.3g, %zu over %.1e\n",
              what, a.n, 100.0 * a.within, a.mean_error, a.worst_ray, a.max_error, a.off, kRayTolerance,
              a.max_depth_error, a.depth_off, kDepthTolerance);
  const auto allowed = static_cast<size_t>(flipped_share * static_cast<double>(a.n));
  if (allowed == 0) {
    EXPECT_LE(a.max_error, kRayTolerance) << what << ": ray " << a.worst_ray;
  }
  EXPECT_LE(a.off, allowed) << what << ": rays off by more than " << kRayTolerance;
  EXPECT_LE(a.depth_off, allowed) << what << ": rays whose depth is off by more than " << kDepthTolerance;
}

}  // namespace foveart::gpu_engine::testing
