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
FoveatedResult FoveatedRenderer::render(engine::Tracer&, glm::vec2, engine::Image*) {
  FoveatedResult r;
  r.error = state_->error;
  return r;
}

#else

namespace {

double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

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
  // Per-frame buffers, reused: colours of the traced points, and for every point
  // of the set its colour and the frame in which it was last traced, side by
  // side so a gather tap touches one cache line (no clearing per frame).
  struct PointSlot {
    glm::vec3 rgb{0.0f};
    uint32_t frame = 0;
  };
  std::vector<glm::vec3> visible_rgb;
  std::vector<PointSlot> slots;
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
    st.slots.assign(st.tables.points.size(), State::PointSlot{});
    st.precompute_ms = ms_since(t0);
  } catch (const std::exception& e) {
    st.error = std::string("foveation: ") + e.what();
  }
}

FoveatedRenderer::~FoveatedRenderer() = default;
const std::string& FoveatedRenderer::error() const { return state_->error; }
double FoveatedRenderer::precompute_ms() const { return state_->precompute_ms; }

FoveatedResult FoveatedRenderer::render(engine::Tracer& tracer, glm::vec2 gaze_px, engine::Image* out) {
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
    // Per frame: visible points, then spp samples per point in its disc, traced.
    // Sample positions are foveation::unit_disc_sample, exactly as
    // generate_ray_samples places them, but made inside the parallel batches.
    auto t0 = std::chrono::steady_clock::now();
    const foveation::GazeMapping mapping =
        foveation::map_gaze(static_cast<int>(view.width_px), static_cast<int>(view.height_px), gaze_px);
    const foveation::VisiblePoints visible = foveation::select_visible_points(points, mapping);
    r.samples_ms = ms_since(t0);
    const uint64_t seed = st.request.seed;
    const engine::SampleFn sample = [&](uint64_t v, uint32_t s) {
      const uint32_t p = visible.point_index[v];
      return visible.screen_px[v] + foveation::unit_disc_sample(seed, p, static_cast<int>(s)) * points.radius_px[p];
    };
    engine::RenderSettings settings;
    settings.threads = st.threads;
    settings.spp = st.request.spp;
    const engine::RenderResult traced = engine::trace_points(&foveart_engine_trace_rays, &tracer, view, visible.size(),
                                                             sample, visible.point_index, settings, &st.visible_rgb);
    r.trace_ms = ms_since(t0);
    r.points = visible.size();
    if (traced.status != FOVEART_RESULT_SUCCESS) {
      r.error = "engine callback failed with status " + std::to_string(traced.status);
      return r;
    }

    t0 = std::chrono::steady_clock::now();
    out->width = view.width_px;
    out->height = view.height_px;
    out->rgb.resize(static_cast<size_t>(view.width_px) * view.height_px);
#ifdef FOVEART_HAVE_INTERPOLATION
    if (st.interp) {
      const foveation::PointColors colors = foveation::point_colors_from_list(
          points.size(), visible.point_index,
          std::span<const float>(&st.visible_rgb.data()->x, 3 * st.visible_rgb.size()));
      foveation::GatherOptions go;
      go.threads = st.threads;
      foveation::gather(st.tables.neighbors, st.interp->table, colors, mapping, st.gathered, go);
      for (size_t i = 0; i < out->rgb.size(); ++i)
        out->rgb[i] = glm::vec3(st.gathered.rgb[3 * i], st.gathered.rgb[3 * i + 1], st.gathered.rgb[3 * i + 2]);
      r.reconstruct_ms = ms_since(t0);
      return r;
    }
#endif
    // NN: every pixel takes the colour of its nearest traced point.
    const uint32_t frame = ++st.frame;
    for (size_t v = 0; v < visible.size(); ++v) {
      const uint32_t p = visible.point_index[v];
      st.slots[p] = State::PointSlot{st.visible_rgb[v], frame};
    }
    const foveation::NeighborTable& nt = st.tables.neighbors;
    const int k = nt.k();
    parallel_rows(view.height_px, st.threads, [&](uint32_t y0, uint32_t y1) {
      for (uint32_t y = y0; y < y1; ++y) {
        const size_t row = static_cast<size_t>(static_cast<int>(y) + mapping.canvas_from_screen_y_px) *
                           static_cast<size_t>(nt.width_px());
        glm::vec3* dst = out->rgb.data() + static_cast<size_t>(y) * view.width_px;
        for (uint32_t x = 0; x < view.width_px; ++x) {
          const size_t pixel = row + static_cast<size_t>(static_cast<int>(x) + mapping.canvas_from_screen_x_px);
          glm::vec3 c(0.0f);
          for (int j = 0; j < k; ++j) {
            const State::PointSlot& slot = st.slots[nt.neighbor(pixel, j)];
            if (slot.frame == frame) {
              c = slot.rgb;
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

#endif

FoveatedResult render_foveated(engine::Tracer& tracer, const FoveartEyeView& view, const FoveatedRequest& req) {
  FoveatedRenderer renderer(view, req);
  engine::Image image;
  FoveatedResult r = renderer.render(tracer, req.gaze_px, &image);
  r.image = std::move(image);
  return r;
}

}  // namespace foveart::tools
