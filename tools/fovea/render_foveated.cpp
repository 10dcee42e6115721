// Foveated rendering through the engine callback (thesis section 4.2): only the
// visible points of the perceptual point set are traced; every pixel is then
// reconstructed from the traced points through the gaze-independent canvas
// tables (NN here; MSM / RBF through the interpolation module's gather).
// Built against the foveation core when it is part of the build.
#include "render_foveated.hpp"

#include <cmath>

#ifdef FOVEART_HAVE_FOVEATION
#include <foveation/display_model.hpp>
#include <foveation/gaze_mapping.hpp>
#include <foveation/neighbor_table.hpp>
#include <foveation/point_set.hpp>
#include <foveation/point_set_cache.hpp>
#include <foveation/ray_samples.hpp>
#include <foveation/visible_points.hpp>
#ifdef FOVEART_HAVE_INTERPOLATION
#include <foveation/gather.hpp>
#include <foveation/interpolation_cache.hpp>
#include <foveation/interpolation_weights.hpp>
#endif

#include <algorithm>
#include <atomic>
#include <chrono>
#include <exception>
#include <optional>
#include <span>
#include <thread>
#include <vector>
#endif

namespace foveart::tools {

#ifndef FOVEART_HAVE_FOVEATION

bool foveated_available() { return false; }

std::optional<PresetGeometry> preset_geometry(const std::string& preset) {
  if (preset != "fove") return std::nullopt;
  const double d = 0.5 * 1280.0 / std::tan(0.5 * 95.0 * 3.14159265358979 / 180.0);  // FOVE 0, 95 deg
  return PresetGeometry{1280, 1440, std::atan(640.0 / d), std::atan(720.0 / d)};
}

struct FoveatedRenderer::State {
  std::string error = "foveated rendering needs the foveation core, which is not part of this build";
};
FoveatedRenderer::FoveatedRenderer(const FoveartEyeView&, const FoveatedRequest&) : state_(std::make_unique<State>()) {}
FoveatedRenderer::~FoveatedRenderer() = default;
const std::string& FoveatedRenderer::error() const { return state_->error; }
double FoveatedRenderer::precompute_ms() const { return 0.0; }
FoveatedResult FoveatedRenderer::render(engine::Tracer& tracer, glm::vec2 gaze_px, engine::Image* out) {
  return render(&foveart_engine_trace_rays, &tracer, gaze_px, out);
}
FoveatedResult FoveatedRenderer::render(FoveartTraceRaysFn, void*, glm::vec2, engine::Image*) {
  FoveatedResult r;
  r.error = state_->error;
  return r;
}
std::vector<uint32_t> FoveatedRenderer::points_per_tile(glm::vec2, uint32_t, uint32_t, uint32_t, uint32_t) const {
  return {};
}

#else

namespace {

double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

// A point's colour and, in `a`, its validity stamp; all points of the set.
#ifdef FOVEART_HAVE_INTERPOLATION
using Rgba = foveation::Rgba;
using PointSlots = foveation::PointColors;  // what gather reads
#else
struct alignas(16) Rgba {
  float r = 0.0f, g = 0.0f, b = 0.0f, a = 0.0f;
};
struct PointSlots {
  std::vector<Rgba> rgba;
  size_t size() const { return rgba.size(); }
};
#endif

// Rays per engine callback call, and set points per parallel work item (one or
// two batches at the fovea: contiguous in Morton order, small enough that the
// last item of a frame leaves the other thread idle only briefly).
constexpr uint32_t kBatchRays = 4096;
constexpr uint64_t kChunkPoints = 8192;
// Sample offsets are precomputed up to this many (64 MB); beyond, made per frame.
constexpr size_t kMaxPrecomputedSamples = size_t{8} << 20;

template <typename Rows>
void parallel_rows(uint32_t height, int threads, Rows&& rows) {
  std::atomic<uint32_t> next{0};
  auto run = [&] {
    for (uint32_t y; (y = next.fetch_add(8)) < height;) rows(y, std::min(height, y + 8));
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(run);
  run();
  for (std::thread& th : pool) th.join();
}

}  // namespace

bool foveated_available() { return true; }

std::optional<PresetGeometry> preset_geometry(const std::string& preset) {
  const std::optional<foveation::DisplayModel> d = foveation::display_preset(preset);
  if (!d || !d->validate().empty()) return std::nullopt;
  // Pinhole: D pixels from the eye, the image spans +-W/2 and +-H/2.
  return PresetGeometry{d->width_px, d->height_px, std::atan(0.5 * d->width_px / d->view_distance_px),
                        std::atan(0.5 * d->height_px / d->view_distance_px)};
}

struct FoveatedRenderer::State {
  FoveartEyeView view{};
  FoveatedRequest request;
  int threads = 1;
  std::string error;
  double precompute_ms = 0.0;
  foveation::FoveationTables tables;
#ifdef FOVEART_HAVE_INTERPOLATION
  std::optional<foveation::CachedTable> interp;
  foveation::ImageRgb gathered;
#endif
  // Gaze-independent ray sample offsets, sample s of point i at [i * spp + s]:
  // unit_disc_sample * radius, made once (empty when too large: made per frame).
  std::vector<glm::vec2> sample_offset_px;
  // One slot per point of the set, written by the trace batches straight at the
  // point's index: its colour and, in `a`, the stamp of the frame that traced it
  // (NN: the frame number, so nothing is cleared per frame; MSM/RBF: 1 after a
  // clear, gather's validity flag).
  PointSlots slots;
  uint32_t frame = 0;
};

FoveatedRenderer::FoveatedRenderer(const FoveartEyeView& view, const FoveatedRequest& req)
    : state_(std::make_unique<State>()) {
  State& st = *state_;
  st.view = view;
  st.request = req;
  st.threads = req.threads > 0 ? req.threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  try {
    const auto t0 = std::chrono::steady_clock::now();
    std::optional<foveation::DisplayModel> preset = foveation::display_preset(req.preset);
    if (!preset) {
      st.error = "unknown display preset '" + req.preset + "'";
      return;
    }
    foveation::DisplayModel display = *preset;
    if (req.horizontal_fov_deg)
      display = foveation::DisplayModel::from_fov(static_cast<int>(view.width_px), static_cast<int>(view.height_px),
                                                  *req.horizontal_fov_deg);
    else if (static_cast<uint32_t>(display.width_px) != view.width_px ||
             static_cast<uint32_t>(display.height_px) != view.height_px)
      display = foveation::DisplayModel::from_fov(static_cast<int>(view.width_px), static_cast<int>(view.height_px),
                                                  preset->horizontal_fov_deg());
    display.scale = req.scale;
    if (std::string bad = display.validate(); !bad.empty()) {
      st.error = "display: " + bad;
      return;
    }
    foveation::PointSetKey key;
    key.display = display;
    key.seed = req.seed;
    // NN reads the first of the k neighbours that was traced. With the thesis's
    // 10 px visible margin the nearest point of every screen pixel is traced
    // (measured: 0 fallbacks at centre and corner gaze), so k = 1 suffices.
    key.k = std::max(req.k, 1);
    std::optional<std::filesystem::path> cache;
    if (!req.cache_dir.empty()) cache = std::filesystem::path(req.cache_dir);
    st.tables = foveation::load_or_build_tables(cache, key);
#ifdef FOVEART_HAVE_INTERPOLATION
    if (req.method != "nn") {  // MSM / RBF: per-canvas-pixel weights (issue 3)
      const std::optional<foveation::InterpMethod> method = foveation::parse_method(req.method);
      if (!method) {
        st.error = "unknown interpolation method '" + req.method + "'";
        return;
      }
      foveation::InterpOptions io;
      io.method = *method;
      io.k = req.k;
      st.interp = foveation::load_or_build_interpolation_table(cache, key, st.tables.points, st.tables.neighbors, io,
                                                               std::nullopt, st.threads);
    }
#else
    if (req.method != "nn") {
      st.error = "--method " + req.method + " needs the interpolation module, which is not part of this build";
      return;
    }
#endif
    st.slots.rgba.assign(st.tables.points.size(), Rgba{});
    const size_t spp = static_cast<size_t>(std::max(req.spp, 1));
    if (st.tables.points.size() * spp <= kMaxPrecomputedSamples) {
      const foveation::PointSet& points = st.tables.points;
      st.sample_offset_px.resize(points.size() * spp);
      engine::parallel_chunks(points.size(), 16384, st.threads, [&](uint64_t first, uint64_t count) {
        for (uint64_t i = first; i < first + count; ++i)
          for (size_t s = 0; s < spp; ++s)
            st.sample_offset_px[i * spp + s] =
                foveation::unit_disc_sample(req.seed, static_cast<uint32_t>(i), static_cast<int>(s)) * points.radius_px[i];
      });
    }
    st.precompute_ms = ms_since(t0);
  } catch (const std::exception& e) {
    st.error = std::string("foveation: ") + e.what();
  }
}

FoveatedRenderer::~FoveatedRenderer() = default;
const std::string& FoveatedRenderer::error() const { return state_->error; }
double FoveatedRenderer::precompute_ms() const { return state_->precompute_ms; }

FoveatedResult FoveatedRenderer::render(engine::Tracer& tracer, glm::vec2 gaze_px, engine::Image* out) {
  return render(&foveart_engine_trace_rays, &tracer, gaze_px, out);
}

FoveatedResult FoveatedRenderer::render(FoveartTraceRaysFn fn, void* user_data, glm::vec2 gaze_px,
                                        engine::Image* out) {
  State& st = *state_;
  FoveatedResult r;
  r.precompute_ms = st.precompute_ms;
  if (!st.error.empty()) {
    r.error = st.error;
    return r;
  }
  try {
    const FoveartEyeView& view = st.view;
    const foveation::PointSet& points = st.tables.points;
    // Per frame, in one parallel pass over the point set (Morton order, so the
    // rays of a packet are neighbours on the screen): each chunk of points keeps
    // the visible ones (foveation::select_visible_points' test, thesis 4.2),
    // casts spp rays per point through its disc (foveation::unit_disc_sample,
    // exactly as generate_ray_samples places them) and writes the mean colour
    // straight into the point's slot. No per-frame arrays, no serial pass.
    auto t0 = std::chrono::steady_clock::now();
    const foveation::GazeMapping mapping =
        foveation::map_gaze(static_cast<int>(view.width_px), static_cast<int>(view.height_px), gaze_px);
#ifdef FOVEART_HAVE_INTERPOLATION
    const bool nn = !st.interp;
#else
    const bool nn = true;
#endif
    if (!nn) {  // gather's validity flag is 1 / 0: clear the slots
      engine::parallel_chunks(st.slots.size(), 65536, st.threads, [&](uint64_t first, uint64_t count) {
        std::fill_n(st.slots.rgba.begin() + static_cast<std::ptrdiff_t>(first), count, Rgba{});
      });
    } else if (++st.frame >= (1u << 24)) {  // the stamp is a float: restart before it gets inexact
      std::fill(st.slots.rgba.begin(), st.slots.rgba.end(), Rgba{});
      st.frame = 1;
    }
    const float stamp = nn ? static_cast<float>(st.frame) : 1.0f;
    r.samples_ms = ms_since(t0);

    const foveation::EyeFrustum frustum = foveation::eye_frustum(view);
    const foveation::EyePose pose = foveation::eye_pose(view);
    const foveation::VisibleRegion visible(mapping);
    const uint32_t spp = static_cast<uint32_t>(std::max(st.request.spp, 1));
    const uint32_t batch_points = std::max<uint32_t>(1, kBatchRays / spp);
    const uint64_t seed = st.request.seed;
    std::atomic<uint64_t> traced_points{0};
    std::atomic<int32_t> status{FOVEART_RESULT_SUCCESS};
    engine::parallel_chunks(points.size(), kChunkPoints, st.threads, [&](uint64_t first, uint64_t count) {
      thread_local engine::RayBatch batch;
      thread_local std::vector<uint32_t> ids;
      batch.resize(static_cast<size_t>(batch_points) * spp);
      ids.resize(batch_points);
      uint32_t n = 0;
      uint64_t done = 0;
      auto flush = [&] {
        const int32_t result = batch.trace(fn, user_data, view, n * spp);
        if (result != FOVEART_RESULT_SUCCESS) {
          int32_t expected = FOVEART_RESULT_SUCCESS;
          status.compare_exchange_strong(expected, result);
        }
        const float inv = 1.0f / static_cast<float>(spp);
        for (uint32_t j = 0, k = 0; j < n; ++j) {
          glm::vec3 sum(0.0f);
          for (uint32_t s = 0; s < spp; ++s, ++k) sum += batch.rgb(k);
          sum *= inv;
          st.slots.rgba[ids[j]] = Rgba{sum.x, sum.y, sum.z, stamp};
        }
        done += n;
        n = 0;
      };
      for (uint64_t i = first; i < first + count; ++i) {
        const glm::vec2 screen = visible.to_screen(points.position_px[i]);
        if (!visible.contains(screen)) continue;
        const uint32_t id = static_cast<uint32_t>(i);
        for (uint32_t s = 0; s < spp; ++s) {
          const glm::vec2 offset = st.sample_offset_px.empty()
                                       ? foveation::unit_disc_sample(seed, id, static_cast<int>(s)) * points.radius_px[i]
                                       : st.sample_offset_px[i * spp + s];
          batch.set_ray(n * spp + s, frustum, pose, screen + offset, id);
        }
        ids[n] = id;
        if (++n == batch_points) flush();
      }
      if (n > 0) flush();
      traced_points.fetch_add(done, std::memory_order_relaxed);
    });
    r.trace_ms = ms_since(t0);
    r.points = traced_points.load();
    if (status.load() != FOVEART_RESULT_SUCCESS) {
      r.error = "engine callback failed with status " + std::to_string(status.load());
      return r;
    }

    t0 = std::chrono::steady_clock::now();
    out->width = view.width_px;
    out->height = view.height_px;
    out->rgb.resize(static_cast<size_t>(view.width_px) * view.height_px);
#ifdef FOVEART_HAVE_INTERPOLATION
    if (st.interp) {
      foveation::GatherOptions go;
      go.threads = st.threads;
      foveation::gather(st.tables.neighbors, st.interp->table, st.slots, mapping, st.gathered, go);
      parallel_rows(view.height_px, st.threads, [&](uint32_t y0r, uint32_t y1r) {
        for (size_t i = static_cast<size_t>(y0r) * view.width_px; i < static_cast<size_t>(y1r) * view.width_px; ++i)
          out->rgb[i] = glm::vec3(st.gathered.rgb[3 * i], st.gathered.rgb[3 * i + 1], st.gathered.rgb[3 * i + 2]);
      });
      r.reconstruct_ms = ms_since(t0);
      return r;
    }
#endif
    // NN: every pixel takes the colour of its nearest point traced this frame.
    const foveation::NeighborTable& nt = st.tables.neighbors;
    const int k = nt.k();
    const Rgba* slots = st.slots.rgba.data();
    parallel_rows(view.height_px, st.threads, [&](uint32_t y0r, uint32_t y1r) {
      for (uint32_t y = y0r; y < y1r; ++y) {
        const size_t row = static_cast<size_t>(static_cast<int>(y) + mapping.canvas_from_screen_y_px) *
                           static_cast<size_t>(nt.width_px());
        glm::vec3* dst = out->rgb.data() + static_cast<size_t>(y) * view.width_px;
        for (uint32_t x = 0; x < view.width_px; ++x) {
          const size_t pixel = row + static_cast<size_t>(static_cast<int>(x) + mapping.canvas_from_screen_x_px);
          glm::vec3 c(0.0f);
          for (int j = 0; j < k; ++j) {
            const Rgba& slot = slots[nt.neighbor(pixel, j)];
            if (slot.a == stamp) {
              c = glm::vec3(slot.r, slot.g, slot.b);
              break;
            }
          }
          dst[x] = c;
        }
      }
    });
    r.reconstruct_ms = ms_since(t0);
  } catch (const std::exception& e) {
    r.error = std::string("foveation: ") + e.what();
  }
  return r;
}

std::vector<uint32_t> FoveatedRenderer::points_per_tile(glm::vec2 gaze_px, uint32_t tile_w, uint32_t tile_h,
                                                       uint32_t tiles_x, uint32_t tiles_y) const {
  const State& st = *state_;
  if (!st.error.empty() || tile_w == 0 || tile_h == 0 || tiles_x == 0 || tiles_y == 0) return {};
  const FoveartEyeView& view = st.view;
  const foveation::GazeMapping mapping =
      foveation::map_gaze(static_cast<int>(view.width_px), static_cast<int>(view.height_px), gaze_px);
  const foveation::VisibleRegion visible(mapping);  // render()'s test
  const float w = static_cast<float>(mapping.screen_width_px), h = static_cast<float>(mapping.screen_height_px);
  std::vector<uint32_t> count(static_cast<size_t>(tiles_x) * tiles_y, 0);
  for (const glm::vec2& p : st.tables.points.position_px) {
    const glm::vec2 screen = visible.to_screen(p);
    if (!visible.contains(screen)) continue;
    const uint32_t tx = std::min(tiles_x - 1, static_cast<uint32_t>(std::clamp(screen.x, 0.0f, w - 1.0f)) / tile_w);
    const uint32_t ty = std::min(tiles_y - 1, static_cast<uint32_t>(std::clamp(screen.y, 0.0f, h - 1.0f)) / tile_h);
    ++count[static_cast<size_t>(ty) * tiles_x + tx];
  }
  return count;
}

#endif

}  // namespace foveart::tools
