// Whole-image rendering through any FoveartTraceRaysFn: the full render the
// foveated frame is measured against. Rays come from foveation's one batch
// builder (foveation/ray_batch.hpp) and are traced on an injected executor.
#pragma once

#include <engine/scene.hpp>

#include <foveation/executor.hpp>
#include <foveation/eye_rays.hpp>
#include <foveation/image.hpp>
#include <foveation/ray_samples.hpp>
#include <foveation/ray_trace.h>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace foveart::engine {

struct RenderSettings {
  int spp = 1;                   // jittered rays per pixel
  uint32_t batch_rays = 4096;    // rays per callback call
  uint64_t seed = 0;             // jitter seed; same seed, same image for any thread count
  bool jitter = true;            // false: every ray through its pixel's centre
  foveation::PixelFilter pixel_filter = foveation::PixelFilter::box;  // what the jitter follows
  // Optional: per pixel the distance (m) along its first ray to the hit (+inf:
  // a miss), as the engine returns it in the batch (NaN if it returns none).
  std::vector<float>* out_depth_m = nullptr;
};

struct RenderResult {
  int32_t status = FOVEART_RESULT_SUCCESS;  // first failing callback status, if any
  double trace_ms = 0.0;                   // wall time of ray generation + tracing
  // The image is traced tile by tile (one callback call per tile);
  // tile_ms[ty * tiles_x + tx] is the time its thread spent on tile (tx, ty):
  // a map of what the scene costs where.
  uint32_t tile_width_px = 0;
  uint32_t tile_height_px = 0;
  uint32_t tiles_x = 0;
  std::vector<double> tile_ms;
};

// The full render: spp jittered rays in every pixel (foveation::pixel_jitter), averaged, into *out_image
// (linear RGB); traced in tiles of (up to) 64 px width and batch_rays / (64 spp)
// rows (packets of 16 neighbours along a row), spread over the executor.
RenderResult render_full(FoveartTraceRaysFn fn, void* user_data, const FoveartEyeView& view,
                         const RenderSettings& settings, foveation::ImageRgb* out_image, foveation::Executor& executor);

// The FOVE 0 headset per eye: 1280x1440 px, 95 deg horizontal field of view,
// square pixels; eye 0 (left) / 1 (right) 32 mm either side of the head pose.
FoveartEyeView fove_eye_view(uint32_t eye_index, const Camera& head);

// The head pose to render a scene from: its camera, or one that frames it.
Camera scene_head(const Scene& scene);

}  // namespace foveart::engine
