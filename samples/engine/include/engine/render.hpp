// Whole-image rendering through any FoveartTraceRaysFn: the way FoveaRT (or a
// tool) drives an engine. Rays are generated from an eye view with
// foveation/eye_rays.hpp, cut into batches and traced from a pool of threads.
#pragma once

#include <engine/scene.hpp>

#include <foveation/ray_trace.h>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace foveart::engine {

struct Image {
  uint32_t width = 0;
  uint32_t height = 0;
  std::vector<glm::vec3> rgb;  // linear, row-major, top row first
};

struct RenderSettings {
  int spp = 1;                   // jittered rays per pixel (or per point)
  int threads = 0;               // 0 = all hardware threads
  uint32_t batch_rays = 4096;    // rays per callback call
  uint64_t seed = 0;             // jitter seed; same seed, same image for any thread count
};

struct RenderResult {
  int32_t status = FOVEART_RESULT_SUCCESS;  // first failing callback status, if any
  double trace_ms = 0.0;                   // wall time of ray generation + tracing
};

// spp jittered rays in every pixel, averaged.
RenderResult render_full(FoveartTraceRaysFn fn, void* user_data, const FoveartEyeView& view,
                         const RenderSettings& settings, Image* out_image);

// One ray per given screen position (e.g. foveation::RaySamples): out_rgb gets
// one linear colour per sample, in order; point_index (may be empty) is passed
// through to the engine.
RenderResult trace_samples(FoveartTraceRaysFn fn, void* user_data, const FoveartEyeView& view,
                           const std::vector<glm::vec2>& sample_px, const std::vector<uint32_t>& point_index,
                           const RenderSettings& settings, std::vector<glm::vec3>* out_rgb);

// The FOVE 0 headset per eye: 1280x1440 px, 95 deg horizontal field of view,
// square pixels; eye 0 (left) / 1 (right) 32 mm either side of the head pose.
FoveartEyeView fove_eye_view(uint32_t eye_index, const Camera& head);

// The head pose to render a scene from: its camera, or one that frames it.
Camera scene_head(const Scene& scene);

// 8-bit sRGB PNG (values clamped to [0,1]). Returns false with *error set.
bool write_png(const Image& image, const std::string& path, std::string* error);

// Deterministic jitter in [0,1)^2 for (index, sample, seed).
glm::vec2 jitter(uint64_t index, uint32_t sample, uint64_t seed);

}  // namespace foveart::engine
