// Whole-image rendering through any FoveartTraceRaysFn: the way FoveaRT (or a
// tool) drives an engine. Rays are generated from an eye view with
// foveation/eye_rays.hpp, cut into batches and traced from a pool of threads.
#pragma once

#include <engine/scene.hpp>

#include <foveation/eye_rays.hpp>
#include <foveation/ray_trace.h>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <cstdint>
#include <functional>
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
  // render_full only: the image is traced tile by tile (one callback call per
  // tile); tile_ms[ty * tiles_x + tx] is the time its thread spent on tile
  // (tx, ty) — a map of what the scene costs where.
  uint32_t tile_width_px = 0;
  uint32_t tile_height_px = 0;
  uint32_t tiles_x = 0;
  std::vector<double> tile_ms;
};

// spp jittered rays in every pixel, averaged; traced in tiles of (up to) 64 px
// width and batch_rays / (64 spp) rows (packets of 16 neighbours along a row).
RenderResult render_full(FoveartTraceRaysFn fn, void* user_data, const FoveartEyeView& view,
                         const RenderSettings& settings, Image* out_image);

// One ray per given screen position (e.g. foveation::RaySamples): out_rgb gets
// one linear colour per sample, in order; point_index (may be empty) is passed
// through to the engine.
RenderResult trace_samples(FoveartTraceRaysFn fn, void* user_data, const FoveartEyeView& view,
                           const std::vector<glm::vec2>& sample_px, const std::vector<uint32_t>& point_index,
                           const RenderSettings& settings, std::vector<glm::vec3>* out_rgb);

// The building blocks of the drivers above, for callers that make their own
// rays (e.g. the foveated renderer): a reusable batch for one callback call and
// a chunked parallel loop.

// Rays of one callback call, kept from call to call (one per thread) so that
// nothing is allocated per batch once it has grown to the batch size.
class RayBatch {
 public:
  void resize(size_t n);
  // Ray i through screen position p of the view (origin at the eye), for point `point`.
  void set_ray(size_t i, const foveation::EyeFrustum& f, const foveation::EyePose& pose, glm::vec2 p, uint32_t point) {
    const glm::vec3 d = foveation::eye_ray_direction(f, pose, p);
    float* o = origins_.data() + 3 * i;
    float* dir = directions_.data() + 3 * i;
    o[0] = pose.position_m.x;
    o[1] = pose.position_m.y;
    o[2] = pose.position_m.z;
    dir[0] = d.x;
    dir[1] = d.y;
    dir[2] = d.z;
    sample_px_[2 * i] = p.x;
    sample_px_[2 * i + 1] = p.y;
    point_index_[i] = point;
  }
  // Calls fn for rays [0, n); returns its status.
  int32_t trace(FoveartTraceRaysFn fn, void* user_data, const FoveartEyeView& view, uint32_t n);
  glm::vec3 rgb(size_t i) const { return glm::vec3(rgb_[3 * i], rgb_[3 * i + 1], rgb_[3 * i + 2]); }

 private:
  std::vector<float> origins_, directions_, sample_px_, rgb_;
  std::vector<uint32_t> point_index_;
};

// Runs work(first, count) over [0, n) in chunks of `chunk` items from `threads`
// threads (0 = all hardware threads; the calling thread is one of them).
void parallel_chunks(uint64_t n, uint64_t chunk, int threads, const std::function<void(uint64_t, uint64_t)>& work);

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
