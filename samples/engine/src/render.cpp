// Whole-image rendering through the engine callback, multithreaded.
#include <engine/render.hpp>

#include <foveation/device.hpp>
#include <foveation/elapsed.hpp>
#include <foveation/eye_rays.hpp>
#include <foveation/ray_batch.hpp>
#include <foveation/ray_samples.hpp>

#include <glm/trigonometric.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>

namespace foveart::engine {
namespace {

using foveation::ms_since;

}  // namespace

RenderResult render_full(FoveartTraceRaysFn fn, void* user_data, const FoveartEyeView& view,
                         const RenderSettings& settings, foveation::ImageRgb* out, foveation::Executor& executor) {
  const auto t0 = std::chrono::steady_clock::now();
  RenderResult result;
  if (out->width_px != static_cast<int>(view.width_px) || out->height_px != static_cast<int>(view.height_px)) {
    *out = foveation::ImageRgb(static_cast<int>(view.width_px), static_cast<int>(view.height_px));  // every pixel is written below
  }
  const uint32_t spp = static_cast<uint32_t>(std::max(settings.spp, 1));
  constexpr uint32_t kTileWidth = 64;
  const uint32_t batch_pixels = std::max<uint32_t>(1, settings.batch_rays / spp);
  const uint32_t tile_w = std::min({kTileWidth, view.width_px, batch_pixels});
  const uint32_t tile_h = std::max<uint32_t>(1, batch_pixels / tile_w);
  const uint32_t tiles_x = (view.width_px + tile_w - 1) / tile_w;
  const uint32_t tiles_y = (view.height_px + tile_h - 1) / tile_h;
  result.tile_width_px = tile_w;
  result.tile_height_px = tile_h;
  result.tiles_x = tiles_x;
  result.tile_ms.assign(static_cast<size_t>(tiles_x) * tiles_y, 0.0);
  std::atomic<int32_t> status{FOVEART_RESULT_SUCCESS};
  std::vector<foveation::RayBatch> batches(executor.thread_count());  // per worker slot
  if (settings.out_depth_m != nullptr) settings.out_depth_m->assign(std::size_t(view.width_px) * view.height_px, NAN);
  executor.parallel_for(result.tile_ms.size(), [&](size_t tile, unsigned worker) {
    const auto tile_t0 = std::chrono::steady_clock::now();
    const uint32_t x0 = static_cast<uint32_t>(tile % tiles_x) * tile_w;
    const uint32_t y0 = static_cast<uint32_t>(tile / tiles_x) * tile_h;
    const uint32_t x1 = std::min(view.width_px, x0 + tile_w);
    const uint32_t y1 = std::min(view.height_px, y0 + tile_h);
    foveation::RayBatch& b = batches[worker];
    b.resize(static_cast<size_t>(x1 - x0) * (y1 - y0) * spp);
    size_t r = 0;
    for (uint32_t y = y0; y < y1; ++y)
      for (uint32_t x = x0; x < x1; ++x) {
        const uint64_t p = static_cast<uint64_t>(y) * view.width_px + x;
        for (uint32_t s = 0; s < spp; ++s)
          b.set_sample(r++, glm::vec2(static_cast<float>(x), static_cast<float>(y)) +
                                (settings.jitter ? foveation::pixel_jitter(p, s, settings.seed, settings.pixel_filter)
                                                 : glm::vec2(0.5f)),
                       static_cast<uint32_t>(p));
      }
    const int32_t st = b.trace(fn, user_data, view, 0, static_cast<uint32_t>(r));
    if (st != FOVEART_RESULT_SUCCESS) {
      int32_t expected = FOVEART_RESULT_SUCCESS;
      status.compare_exchange_strong(expected, st);
      for (uint32_t y = y0; y < y1; ++y)  // black, not last frame's pixels
        std::fill_n(out->at(static_cast<int>(x0), static_cast<int>(y)), 3 * (x1 - x0), 0.0f);
      return;
    }
    const float inv = 1.0f / static_cast<float>(spp);
    size_t k = 0;
    for (uint32_t y = y0; y < y1; ++y)
      for (uint32_t x = x0; x < x1; ++x) {
        glm::vec3 sum(0.0f);
        for (uint32_t s = 0; s < spp; ++s, ++k) sum += b.rgb(k);
        if (settings.out_depth_m != nullptr)
          (*settings.out_depth_m)[static_cast<size_t>(y) * view.width_px + x] = b.depth_m(k - spp);
        float* px = out->at(static_cast<int>(x), static_cast<int>(y));
        px[0] = sum.r * inv;
        px[1] = sum.g * inv;
        px[2] = sum.b * inv;
      }
    result.tile_ms[tile] = ms_since(tile_t0);
  });
  result.status = status.load();
  result.trace_ms = ms_since(t0);
  return result;
}

FoveartEyeView fove_eye_view(uint32_t eye_index, const Camera& head) {
  // The one FOVE 0 description, as the simulated runtime and display_preset("fove") read it.
  const foveation::HeadsetDescription fove = foveation::fove0();
  const foveation::EyeFovRad& fov = fove.eye_fov_rad;
  foveation::EyePose pose;
  const float side_m = static_cast<float>(fove.eye_offset_x_m(eye_index));
  pose.orientation = head.orientation;
  pose.position_m = head.position_m + head.orientation * glm::vec3(side_m, 0.0f, 0.0f);
  return foveation::make_eye_view(eye_index, static_cast<uint32_t>(fove.eye_width_px),
                                  static_cast<uint32_t>(fove.eye_height_px), pose, static_cast<float>(fov.left),
                                  static_cast<float>(fov.right), static_cast<float>(fov.up),
                                  static_cast<float>(fov.down));
}

Camera scene_head(const Scene& scene) { return scene.camera ? *scene.camera : framing_camera(scene); }

}  // namespace foveart::engine
