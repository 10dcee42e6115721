// Foveated rendering through the engine callback (thesis section 4.2): only the
// visible points of the perceptual point set are traced; every pixel then reads
// the colour of its nearest traced point through the gaze-independent
// neighbour table. Built only when the foveation core is part of the build.
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
#include <cmath>
#include <exception>
#include <optional>
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

FoveatedResult render_foveated(engine::Tracer&, const FoveartEyeView&, const FoveatedRequest&) {
  FoveatedResult r;
  r.error = "foveated rendering needs the foveation core, which is not part of this build";
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

FoveatedResult render_foveated(engine::Tracer& tracer, const FoveartEyeView& view, const FoveatedRequest& req) {
  FoveatedResult r;
  try {
    std::optional<foveation::DisplayModel> preset = foveation::display_preset(req.preset);
    if (!preset) {
      r.error = "unknown display preset '" + req.preset + "'";
      return r;
    }
    foveation::DisplayModel display = *preset;
    if (static_cast<uint32_t>(display.width_px) != view.width_px ||
        static_cast<uint32_t>(display.height_px) != view.height_px)
      display = foveation::DisplayModel::from_fov(static_cast<int>(view.width_px), static_cast<int>(view.height_px),
                                                  preset->horizontal_fov_deg());
    display.scale = req.scale;
    if (std::string bad = display.validate(); !bad.empty()) {
      r.error = "display: " + bad;
      return r;
    }
    const int threads = req.threads > 0 ? req.threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));

    // Precomputed, gaze-independent tables (cached on disk when asked to).
    auto t0 = std::chrono::steady_clock::now();
    foveation::PointSetKey key;
    key.display = display;
    key.seed = req.seed;
    // NN reads the first of the k neighbours that was traced. With the thesis's
    // 10 px visible margin the nearest point of every screen pixel is traced
    // (measured: 0 fallbacks at centre and corner gaze), so k = 1 suffices.
    key.k = std::max(req.k, 1);
    std::optional<std::filesystem::path> cache;
    if (!req.cache_dir.empty()) cache = std::filesystem::path(req.cache_dir);
    const foveation::FoveationTables tables = foveation::load_or_build_tables(cache, key);
#ifdef FOVEART_HAVE_INTERPOLATION
    // MSM / RBF: per-canvas-pixel weights from the interpolation module (issue 3).
    std::optional<foveation::CachedTable> interp;
    if (req.method != "nn") {
      foveation::InterpOptions io;
      const std::optional<foveation::InterpMethod> method = foveation::parse_method(req.method);
      if (!method) {
        r.error = "unknown interpolation method '" + req.method + "'";
        return r;
      }
      io.method = *method;
      io.k = req.k;
      interp = foveation::load_or_build_interpolation_table(cache, key, tables.points, tables.neighbors, io,
                                                            std::nullopt, threads);
    }
#else
    if (req.method != "nn") {
      r.error = "--method " + req.method + " needs the interpolation module, which is not part of this build";
      return r;
    }
#endif
    r.precompute_ms = ms_since(t0);

    // Per frame: visible points, ray samples, tracing.
    t0 = std::chrono::steady_clock::now();
    const foveation::GazeMapping mapping =
        foveation::map_gaze(static_cast<int>(view.width_px), static_cast<int>(view.height_px), req.gaze_px);
    const foveation::VisiblePoints visible = foveation::select_visible_points(tables.points, mapping);
    const foveation::RaySamples samples = foveation::generate_ray_samples(tables.points, visible, req.spp, req.seed);
    r.samples_ms = ms_since(t0);
    engine::RenderSettings settings;
    settings.threads = threads;
    std::vector<glm::vec3> sample_rgb;
    const engine::RenderResult traced = engine::trace_samples(&foveart_engine_trace_rays, &tracer, view,
                                                              samples.sample_px, samples.point_index, settings, &sample_rgb);
    r.trace_ms = ms_since(t0);
    r.points = visible.size();
    if (traced.status != FOVEART_RESULT_SUCCESS) {
      r.error = "engine callback failed with status " + std::to_string(traced.status);
      return r;
    }

    // One colour per point (mean of its samples), then nearest traced point per pixel.
    t0 = std::chrono::steady_clock::now();
#ifdef FOVEART_HAVE_INTERPOLATION
    if (interp) {
      const size_t n_spp = static_cast<size_t>(samples.spp);
      std::vector<float> rgb(3 * visible.size());
      for (size_t v = 0; v < visible.size(); ++v) {
        glm::vec3 sum(0.0f);
        for (size_t s = 0; s < n_spp; ++s) sum += sample_rgb[v * n_spp + s];
        sum /= static_cast<float>(n_spp);
        rgb[3 * v] = sum.x;
        rgb[3 * v + 1] = sum.y;
        rgb[3 * v + 2] = sum.z;
      }
      const foveation::PointColors colors =
          foveation::point_colors_from_list(tables.points.size(), visible.point_index, rgb);
      foveation::ImageRgb img;
      foveation::GatherOptions go;
      go.threads = threads;
      foveation::gather(tables.neighbors, interp->table, colors, mapping, img, go);
      r.image.width = view.width_px;
      r.image.height = view.height_px;
      r.image.rgb.resize(img.pixel_count());
      for (size_t i = 0; i < img.pixel_count(); ++i)
        r.image.rgb[i] = glm::vec3(img.rgb[3 * i], img.rgb[3 * i + 1], img.rgb[3 * i + 2]);
      r.reconstruct_ms = ms_since(t0);
      return r;
    }
#endif
    const size_t spp = static_cast<size_t>(samples.spp);
    std::vector<glm::vec3> point_rgb(tables.points.size(), glm::vec3(0.0f));
    std::vector<uint8_t> traced_point(tables.points.size(), 0);
    const float inv = 1.0f / static_cast<float>(spp);
    for (size_t v = 0; v < visible.size(); ++v) {
      glm::vec3 sum(0.0f);
      for (size_t s = 0; s < spp; ++s) sum += sample_rgb[v * spp + s];
      const uint32_t p = visible.point_index[v];
      point_rgb[p] = sum * inv;
      traced_point[p] = 1;
    }
    r.image.width = view.width_px;
    r.image.height = view.height_px;
    r.image.rgb.assign(static_cast<size_t>(view.width_px) * view.height_px, glm::vec3(0.0f));
    const foveation::NeighborTable& nt = tables.neighbors;
    const int k = nt.k();
    parallel_rows(view.height_px, threads, [&](uint32_t y0, uint32_t y1) {
      for (uint32_t y = y0; y < y1; ++y) {
        const size_t row = static_cast<size_t>(static_cast<int>(y) + mapping.canvas_from_screen_y_px) *
                           static_cast<size_t>(nt.width_px());
        for (uint32_t x = 0; x < view.width_px; ++x) {
          const size_t pixel = row + static_cast<size_t>(static_cast<int>(x) + mapping.canvas_from_screen_x_px);
          for (int j = 0; j < k; ++j) {
            const uint32_t p = nt.neighbor(pixel, j);
            if (traced_point[p]) {
              r.image.rgb[static_cast<size_t>(y) * view.width_px + x] = point_rgb[p];
              break;
            }
          }
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

}  // namespace foveart::tools
