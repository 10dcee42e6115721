// The ray footprint's texture level of detail on the GPU engine: a finely
// textured checkerboard floor seen at 30 deg from the gaze along the built-in
// scripted motion (eval::motion_frames), one jittered ray per foveated point
// (its disc at 30 deg on the FOVE 0, thesis eq. 4) each frame, flickers less
// against the converged disc average (eval::TemporalError) with the footprint
// (XrFoveatedDeviceRayFootprintFOVEART) than without. Runs on lavapipe; prints the numbers
// (bench/footprint_flicker.sh writes them into docs/results/footprint_flicker.md).
#include <gpu_engine/gpu_tracer.hpp>

#include <eval/motion_views.hpp>
#include <eval/temporal_metrics.hpp>
#include <foveation/device.hpp>
#include <foveation/display_model.hpp>
#include <foveation/eye_rays.hpp>

#include "gpu_trace_fixtures.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <vector>

namespace {

using foveart::engine::Scene;
using foveart::gpu_engine::GpuTracer;
using foveart::layer::DevicePreference;
using namespace foveart::gpu_engine::testing;

constexpr int kPatchSide = 20;        // points per side of the patch at 30 deg
constexpr int kReferenceRays = 48;    // jittered rays per point of the converged reference
constexpr int kFrames = 10;
constexpr double kEccentricityDeg = 30.0;
constexpr std::size_t kRing30 = 5;    // metrics::kRingEdgesDeg's [30, 45) ring

TestGpu& footprint_gpu() {
  static TestGpu g(DevicePreference::cpu, false);
  return g;
}

// A 40 x 40 m floor with a 256 x 256 checkerboard of 2-texel squares repeated 64 times
// across it (4.9 mm squares), lit by the ambient term alone.
Scene checkerboard_floor() {
  Scene s;
  s.source = "checkerboard floor";
  s.ambient = glm::vec3(1.0f);
  foveart::engine::Material m;
  m.roughness = 1.0f;
  m.metallic = 0.0f;
  m.base_color_texture = 0;
  s.materials.push_back(m);
  foveart::engine::Texture t;
  t.width = t.height = 256;
  for (uint32_t y = 0; y < t.height; ++y)
    for (uint32_t x = 0; x < t.width; ++x) t.texels.push_back(glm::vec4(glm::vec3(((x / 2 + y / 2) % 2) ? 1.0f : 0.0f), 1.0f));
  s.textures.push_back(t);
  add_floor(s, 20.0f, 0);
  for (glm::vec2& uv : s.mesh.uv0) uv *= 64.0f;
  return s;
}

// The disc a point at 30 deg from the gaze has on the FOVE 0 (thesis eq. 4): its distance from
// the gaze and radius, pixels.
struct Disc {
  double distance_px = 0.0;
  double radius_px = 0.0;
};
Disc disc_at_30_deg() {
  const foveart::foveation::HeadsetDescription fove = foveart::foveation::fove0();
  const foveart::foveation::DisplayModel display = foveart::foveation::DisplayModel::from_fov(
      fove.eye_width_px, fove.eye_height_px, fove.horizontal_fov_rad() * 180.0 / 3.141592653589793);
  Disc d;
  while (display.ecc_deg(d.distance_px) < kEccentricityDeg) d.distance_px += 1.0;
  d.radius_px = display.radius_px(d.distance_px);
  return d;
}

// A fixed LCG's next value in [0, 1).
float next_unit(uint32_t& state) {
  state = state * 1664525u + 1013904223u;
  return static_cast<float>(state >> 8) / 16777216.0f;
}

// Per point of the patch right of the gaze: `rays_per_point` rays jittered uniformly in its disc
// (seeded by `seed`), and its footprint, the angle of the disc radius at the eye (device_rays.comp).
struct PatchRays {
  Rays rays;
  std::vector<float> footprint_rad;
};
PatchRays patch_rays(const foveart::eval::MotionFrame& frame, const Disc& disc, int rays_per_point, uint32_t seed) {
  const foveart::foveation::EyeFrustum f = foveart::foveation::eye_frustum(frame.view);
  const foveart::foveation::EyePose pose = foveart::foveation::eye_pose(frame.view);
  const auto r = static_cast<float>(disc.radius_px);
  const glm::vec2 centre = frame.gaze_px + glm::vec2(static_cast<float>(disc.distance_px), 0.0f);
  PatchRays out;
  uint32_t state = seed;
  for (int y = 0; y < kPatchSide; ++y)
    for (int x = 0; x < kPatchSide; ++x) {
      const glm::vec2 point = centre + 2.0f * r * glm::vec2(x - kPatchSide / 2, y - kPatchSide / 2);
      const glm::vec3 d0 = foveart::foveation::eye_ray_direction(f, pose, point);
      const glm::vec3 d1 = foveart::foveation::eye_ray_direction(f, pose, point + glm::vec2(r, 0.0f));
      const float footprint = 2.0f * std::asin(0.5f * glm::length(d1 - d0));
      for (int k = 0; k < rays_per_point; ++k) {
        const float radius = r * std::sqrt(next_unit(state)), angle = 6.2831853f * next_unit(state);
        const glm::vec2 sample = point + radius * glm::vec2(std::cos(angle), std::sin(angle));
        out.rays.origin.push_back(pose.position_m);
        out.rays.dir.push_back(foveart::foveation::eye_ray_direction(f, pose, sample));
        out.footprint_rad.push_back(footprint);
      }
    }
  return out;
}

// The patch as an image, a pixel per point: the mean of its rays' radiance, with or without footprints.
foveart::foveation::ImageRgb trace_patch(GpuTracer& tracer, const PatchRays& patch, int rays_per_point,
                                         bool footprint) {
  TestGpu& gpu = footprint_gpu();
  DeviceBatch b(gpu, patch.rays);
  const auto n = static_cast<VkDeviceSize>(patch.footprint_rad.size());
  HostBuffer footprints(gpu, 4 * n);
  std::memcpy(footprints.data, patch.footprint_rad.data(), 4 * n);
  XrFoveatedDeviceRayFootprintFOVEART chained{XR_TYPE_FOVEATED_DEVICE_RAY_FOOTPRINT_FOVEART, nullptr,
                                              {footprints.buffer, 0, 4 * n}};
  if (footprint) b.batch.next = &chained;
  EXPECT_TRUE(trace_batch(gpu, tracer, b));
  const std::vector<glm::vec4> colors = b.result();
  foveart::foveation::ImageRgb image(kPatchSide, kPatchSide);
  for (std::size_t p = 0; p < image.pixel_count(); ++p)
    for (int k = 0; k < rays_per_point; ++k)
      for (int c = 0; c < 3; ++c) image.rgb[3 * p + c] += colors[p * rays_per_point + k][c] / float(rays_per_point);
  return image;
}

// Every pixel of the patch in the 30-45 deg ring.
foveart::metrics::EccentricityMap ring_30_map() {
  foveart::metrics::EccentricityMap map;
  map.width_px = map.height_px = kPatchSide;
  map.ring.assign(std::size_t{kPatchSide} * kPatchSide, static_cast<uint8_t>(kRing30));
  map.ring_pixels[kRing30] = map.ring.size();
  return map;
}

TEST(GpuFootprint, TexturedFloorAt30DegFlickersLessWithTheFootprint) {
  if (!footprint_gpu().vk.ok()) GTEST_SKIP() << "no Vulkan device";
  std::string error;
  auto tracer = GpuTracer::create(footprint_gpu().context(), checkerboard_floor(), {}, &error);
  ASSERT_NE(tracer, nullptr) << error;
  const auto motion = foveart::eval::load_motion("builtin", &error);
  ASSERT_TRUE(motion) << error;
  const foveart::eval::MotionWindow window{1.0, 70.0, kFrames};
  ASSERT_TRUE(foveart::eval::check_motion_window(*motion, window, &error)) << error;
  const foveart::foveation::HeadsetDescription fove = foveart::foveation::fove0();
  foveart::foveation::EyePose head;  // 1.6 m above the floor, looking 35 deg down
  head.position_m = {0.0f, 1.6f, 0.0f};
  head.orientation = glm::angleAxis(-0.61f, glm::vec3(1.0f, 0.0f, 0.0f));
  const FoveartEyeView rest = foveart::foveation::make_eye_view(
      0, fove.eye_width_px, fove.eye_height_px, head, float(fove.eye_fov_rad.left), float(fove.eye_fov_rad.right),
      float(fove.eye_fov_rad.up), float(fove.eye_fov_rad.down));
  const Disc disc = disc_at_30_deg();
  foveart::eval::TemporalError with, without;
  const foveart::metrics::EccentricityMap map = ring_30_map();
  for (const foveart::eval::MotionFrame& frame : foveart::eval::motion_frames(*motion, window, rest, head)) {
    const auto seed = static_cast<uint32_t>(frame.index);
    const PatchRays one = patch_rays(frame, disc, 1, 1000u + seed);
    const foveart::foveation::ImageRgb reference =
        trace_patch(*tracer, patch_rays(frame, disc, kReferenceRays, 7u * seed), kReferenceRays, false);
    with.add_frame(trace_patch(*tracer, one, 1, true), reference, map);
    without.add_frame(trace_patch(*tracer, one, 1, false), reference, map);
  }
  const foveart::eval::RingBand band{"30-45 deg", kRing30, kRing30 + 1};
  const double flicker_with = with.pooled(band).flicker_rms, flicker_without = without.pooled(band).flicker_rms;
  // One JSON line, read by bench/footprint_flicker.sh into docs/results/footprint_flicker.md.
  std::printf("[ footprint ] {\"device\": \"%s\", \"eccentricity_deg\": %.1f, \"distance_px\": %.2f, "
              "\"radius_px\": %.2f, \"frames\": %d, \"reference_rays\": %d, \"flicker_rms_with\": %.4f, "
              "\"flicker_rms_without\": %.4f, \"error_mse_with\": %.5f, \"error_mse_without\": %.5f}\n",
              footprint_gpu().vk.name().c_str(), kEccentricityDeg, disc.distance_px, disc.radius_px, kFrames,
              kReferenceRays, flicker_with, flicker_without, with.pooled(band).error_mse, without.pooled(band).error_mse);
  EXPECT_GT(flicker_without, 0.0);
  EXPECT_LT(flicker_with, flicker_without);
  expect_no_validation_errors(footprint_gpu());
}

}  // namespace
