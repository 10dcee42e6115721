// `fovea render`: full-resolution and/or foveated rendering of a glTF scene with
// the sample engine; JSON report of rays per effect and times. The foveated
// frame is foveation::FoveatedView, the one the OpenXR layer runs.
#include "cmd_render.hpp"

#include "content_speedup.hpp"
#include "display_options.hpp"
#include "motion_sequence.hpp"
#include "pfm.hpp"
#include "reference.hpp"
#include "render_metrics.hpp"

#include <engine/gltf_loader.hpp>
#include <engine/render.hpp>
#include <engine/tracer.hpp>

#include <foveation/display_model.hpp>
#include <foveation/executor.hpp>
#include <foveation/foveated_view.hpp>

#include <toolkit/image_io.hpp>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <numeric>
#include <filesystem>
#include <optional>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <sstream>
#include <vector>

namespace foveart::tools {
namespace {

using Json = nlohmann::ordered_json;

double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

Json rays_json(const engine::RayCounts& c) {
  return Json{{"primary", c.primary}, {"shadow", c.shadow}, {"reflection", c.reflection}, {"refraction", c.refraction}};
}

engine::RayCounts minus(const engine::RayCounts& a, const engine::RayCounts& b) {
  return engine::RayCounts{a.primary - b.primary, a.shadow - b.shadow, a.reflection - b.reflection,
                           a.refraction - b.refraction, a.packets - b.packets};
}

// Mean active lanes per 16-wide Embree call: how full (coherent) the packets were.
double lanes_per_packet(const engine::RayCounts& c) {
  return c.packets > 0 ? static_cast<double>(c.total()) / static_cast<double>(c.packets) : 0.0;
}

// Per-frame times of one mode; the report gives the medians (the frame whose
// total is the median, so trace + reconstruct add up to total).
struct FrameTimes {
  std::vector<double> total_ms, trace_ms, reconstruct_ms, samples_ms;
  void add(double trace, double reconstruct, double samples = 0.0) {
    trace_ms.push_back(trace);
    reconstruct_ms.push_back(reconstruct);
    samples_ms.push_back(samples);
    total_ms.push_back(trace + reconstruct);
  }
  size_t median_frame() const {
    std::vector<size_t> order(total_ms.size());
    std::iota(order.begin(), order.end(), size_t{0});
    std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return total_ms[a] < total_ms[b]; });
    return order[order.size() / 2];
  }
  double median_total_ms() const { return total_ms[median_frame()]; }
  double median_trace_ms() const { return trace_ms[median_frame()]; }
  double median_reconstruct_ms() const { return reconstruct_ms[median_frame()]; }
  double median_samples_ms() const { return samples_ms[median_frame()]; }
};

constexpr double kPi = 3.14159265358979323846;

// Per-eye size and symmetric frustum of a display preset.
struct PresetGeometry {
  int width_px = 0;
  int height_px = 0;
  double half_fov_x_rad = 0.0;
  double half_fov_y_rad = 0.0;
};

std::optional<PresetGeometry> preset_geometry(const std::string& preset) {
  const std::optional<foveation::DisplayModel> d = foveation::display_preset(preset);
  if (!d || !d->validate().empty()) return std::nullopt;
  // Pinhole: D pixels from the eye, the image spans +-W/2 and +-H/2.
  return PresetGeometry{d->width_px, d->height_px, std::atan(0.5 * d->width_px / d->view_distance_px),
                        std::atan(0.5 * d->height_px / d->view_distance_px)};
}

}  // namespace

// The display the foveated view's tables are built for: the preset's; for
// another size, the preset's horizontal FOV at that size; for an explicit view
// (--fov), the display the layer builds for that view (display_of_view).
std::optional<foveation::DisplayModel> foveated_display(const RenderOptions& o, const FoveartEyeView& view,
                                                        std::string* error) {
  std::optional<foveation::DisplayModel> display = foveation::display_preset(o.preset);
  if (!display) {
    *error = "unknown display preset '" + o.preset + "'";
    return std::nullopt;
  }
  if (o.fov_deg) {
    display = foveation::display_of_view(view);
  } else if (static_cast<uint32_t>(display->width_px) != view.width_px ||
             static_cast<uint32_t>(display->height_px) != view.height_px) {
    display = foveation::DisplayModel::from_fov(static_cast<int>(view.width_px), static_cast<int>(view.height_px),
                                                display->horizontal_fov_deg());
  }
  display->scale = o.scale;
  // The preset's pattern unless one is asked for (from_fov and display_of_view give the default).
  display->fovea_pattern = foveation::display_preset(o.preset)->fovea_pattern;
  if (!o.pattern.empty()) display->fovea_pattern = *foveation::parse_fovea_pattern(o.pattern);
  if (std::string bad = display->validate(); !bad.empty()) {
    *error = "display: " + bad;
    return std::nullopt;
  }
  return display;
}

int reconstruction_k(const RenderOptions& o) { return o.method == "nn" ? 1 : (o.k > 0 ? o.k : 5); }

std::shared_ptr<const foveation::ViewTables> load_foveated_tables(const RenderOptions& o, const FoveartEyeView& view,
                                                                  const std::optional<std::filesystem::path>& cache_dir,
                                                                  foveation::Executor& executor,
                                                                  const foveation::LogFn& log, std::string* error) {
  const std::optional<foveation::DisplayModel> display = foveated_display(o, view, error);
  if (!display) return nullptr;
  foveation::PointSetKey key;
  key.display = *display;
  key.seed = o.seed;
  foveation::InterpOptions interp;
  interp.method = *foveation::parse_method(o.method);
  interp.k = reconstruction_k(o);
  try {
    return foveation::load_view_tables(cache_dir, key, interp, executor, std::nullopt, {}, log);
  } catch (const std::exception& e) {
    *error = std::string("tables: ") + e.what();
    return nullptr;
  }
}

// Per-eye view of the preset (square pixels, symmetric frustum), optionally resized
// keeping the horizontal field of view; or, with --fov / --pose, exactly the
// given OpenXR view.
FoveartEyeView render_view(const RenderOptions& o, const engine::Scene& scene) {
  const PresetGeometry g = *preset_geometry(o.preset);
  FoveartEyeView view = engine::fove_eye_view(o.eye == "right" ? 1u : 0u, engine::scene_head(scene));
  view.width_px = static_cast<uint32_t>(o.size_px ? o.size_px->x : g.width_px);
  view.height_px = static_cast<uint32_t>(o.size_px ? o.size_px->y : g.height_px);
  const double tan_x = std::tan(g.half_fov_x_rad);
  const double tan_y = o.size_px ? tan_x * o.size_px->y / o.size_px->x : std::tan(g.half_fov_y_rad);
  view.angle_left_rad = static_cast<float>(-g.half_fov_x_rad);
  view.angle_right_rad = static_cast<float>(g.half_fov_x_rad);
  view.angle_up_rad = static_cast<float>(std::atan(tan_y));
  view.angle_down_rad = static_cast<float>(-std::atan(tan_y));
  if (o.fov_deg) {
    float* angles[4] = {&view.angle_left_rad, &view.angle_right_rad, &view.angle_up_rad, &view.angle_down_rad};
    for (int i = 0; i < 4; ++i) *angles[i] = static_cast<float>((*o.fov_deg)[i] * kPi / 180.0);
  }
  if (o.pose) {
    for (int i = 0; i < 3; ++i) view.position_m[i] = static_cast<float>((*o.pose)[i]);
    for (int i = 0; i < 4; ++i) view.orientation_xyzw[i] = static_cast<float>((*o.pose)[3 + i]);
  }
  return view;
}

namespace {

std::string check_view(const RenderOptions& o) {
  if (o.fov_deg) {
    const auto& f = *o.fov_deg;
    for (double a : f)
      if (!std::isfinite(a) || a <= -90.0 || a >= 90.0) return "--fov angles must be finite and inside (-90, 90) degrees";
    if (!(f[0] < f[1])) return "--fov: left must be less than right";
    if (!(f[3] < f[2])) return "--fov: down must be less than up";
  }
  if (o.pose) {
    double norm2 = 0.0;
    for (int i = 0; i < 7; ++i) {
      if (!std::isfinite((*o.pose)[i])) return "--pose values must be finite";
      if (i >= 3) norm2 += (*o.pose)[i] * (*o.pose)[i];
    }
    if (std::abs(norm2 - 1.0) > 1e-3) return "--pose: the quaternion qx,qy,qz,qw must have unit length";
  }
  return "";
}

}  // namespace

engine::TracerOptions render_tracer_options(const RenderOptions& o) {
  engine::TracerOptions t;
  if (!o.without.empty()) {
    std::string unused;
    const engine::Effects left_out = *engine::parse_effects(o.without, &unused);
    t.allowed = engine::Effects::from_bits(engine::Effects::all().bits() & ~left_out.bits());
  }
  return t;
}

std::string check_render_options(const RenderOptions& o) {
  if (o.mode != "full" && o.mode != "foveated" && o.mode != "both") return "--mode must be full, foveated or both";
  if (o.eye != "left" && o.eye != "right") return "--eye must be left or right";
  if (o.method != "nn" && o.method != "msm" && o.method != "rbf-mq") return "--method must be nn, msm or rbf-mq";
  if (!preset_geometry(o.preset)) return "--preset: unknown display preset '" + o.preset + "'";
  if (o.spp < 1 || o.spp > 1024) return "--spp must be in 1..1024";
  if (o.k < 0 || o.k > 20) return "--k must be in 1..20";
  if (!(o.scale > 0.0) || o.scale > 100.0) return "--scale must be in (0, 100]";
  if (!o.pattern.empty() && !foveation::parse_fovea_pattern(o.pattern))
    return "--pattern must be pixel-grid or thesis, got '" + o.pattern + "'";
  if (o.threads < 0) return "--threads must be >= 0";
  if (o.frames < 1 || o.frames > 1000) return "--frames must be in 1..1000";
  if (o.size_px && (o.size_px->x < 8 || o.size_px->y < 8 || o.size_px->x > 16384 || o.size_px->y > 16384))
    return "--size must be between 8 and 16384 pixels per side";
  if (std::string bad = check_view(o); !bad.empty()) return bad;
  if (!o.without.empty()) {
    std::string bad;
    if (!engine::parse_effects(o.without, &bad)) return "--without: " + bad;
  }
  if (!o.reference_spp.empty() && o.reference_spp != "auto") {
    char* end = nullptr;
    const long n = std::strtol(o.reference_spp.c_str(), &end, 10);
    if (end == o.reference_spp.c_str() || *end != '\0' || n < 2 || n > 65536 || n % 2 != 0 || (n > 16 && n % 16 != 0))
      return "--reference-spp must be auto or rays per pixel 2, 4, ..., 16 or a multiple of 16 up to 65536, got '" +
             o.reference_spp + "'";
  }
  if (!o.reference_spp.empty() && !o.reference_file.empty()) return "give --reference-spp or --reference, not both";
  std::vector<std::string> taa;
  if (std::string bad = parse_taa_modes(o.taa, &taa); !bad.empty()) return bad;
  if (o.mode == "full" && taa != std::vector<std::string>{"off"}) return "--taa needs --mode foveated or both";
  if (o.motion.empty()) {
    if (taa.size() > 1) return "--taa: a list of modes needs --motion (one still view has one TAA)";
    if (o.start_s) return "--start-s needs --motion";
    if (o.fps) return "--fps needs --motion";
  } else {
    if (o.pose) return "--pose and --motion exclude each other: the motion gives the head pose";
    if (o.gaze_px) return "--gaze and --motion exclude each other: the motion gives the gaze";
    if (!o.reference_file.empty()) return "--reference FILE is one still image; with --motion use --reference-spp";
  }
  return "";
}

int run_render(const RenderOptions& o, std::ostream& out, std::ostream& err) {
  if (std::string bad = check_render_options(o); !bad.empty()) {
    err << "fovea render: " << bad << "\n";
    return 2;
  }
  if (!o.motion.empty()) return run_render_motion(o, out, err);
  auto t0 = std::chrono::steady_clock::now();
  engine::LoadResult loaded = engine::load_scene(o.scene);
  if (!loaded.ok()) {
    err << "fovea render: " << loaded.error << "\n";
    return 1;
  }
  const double load_ms = ms_since(t0);
  for (const std::string& w : loaded.scene->warnings) err << "fovea render: warning: " << w << "\n";
  t0 = std::chrono::steady_clock::now();
  std::string error;
  std::unique_ptr<engine::Tracer> tracer =
      engine::Tracer::create(std::move(*loaded.scene), render_tracer_options(o), &error);
  if (!tracer) {
    err << "fovea render: " << error << "\n";
    return 1;
  }
  const double build_ms = ms_since(t0);
  const FoveartEyeView view = render_view(o, tracer->scene());
  const glm::vec2 gaze = o.gaze_px.value_or(glm::vec2(0.5f * static_cast<float>(view.width_px),
                                                      0.5f * static_cast<float>(view.height_px)));
  const uint64_t pixels = static_cast<uint64_t>(view.width_px) * view.height_px;

  Json report;
  report["scene"] = tracer->scene().source;
  report["triangles"] = tracer->scene().mesh.triangles.size();
  report["effects"] = engine::to_string(tracer->effects());
  report["eye"] = o.eye;
  report["width"] = view.width_px;
  report["height"] = view.height_px;
  report["gaze"] = {gaze.x, gaze.y};
  auto deg = [](float rad) { return static_cast<double>(rad) * 180.0 / kPi; };
  report["fov_deg"] = {deg(view.angle_left_rad), deg(view.angle_right_rad), deg(view.angle_up_rad),
                       deg(view.angle_down_rad)};
  report["pose"] = {view.position_m[0],        view.position_m[1],        view.position_m[2],
                    view.orientation_xyzw[0], view.orientation_xyzw[1], view.orientation_xyzw[2],
                    view.orientation_xyzw[3]};
  report["spp"] = o.spp;
  report["pixel_filter"] = foveation::pixel_filter_name(o.pixel_filter);
  foveation::Executor executor(static_cast<unsigned>(o.threads));  // every parallel stage of this run
  report["threads"] = executor.thread_count();
  report["load_ms"] = load_ms;
  report["build_ms"] = build_ms;
  report["pixels"] = pixels;
  report["points"] = pixels;  // full mode: one point per pixel; replaced by the visible points below

  // Each mode renders o.frames frames, the modes interleaved (full, foveated,
  // full, ...) so that a slow spell of the machine falls on both; the report
  // gives each mode's median frame. The first frame of each pays for first
  // touches (fresh image memory, the mmap-ed neighbour table, cold caches) and
  // stays in frames_total_ms.
  const bool run_full = o.mode == "full" || o.mode == "both";
  const bool run_foveated = o.mode == "foveated" || o.mode == "both";
  foveation::ImageRgb full;
  engine::RenderSettings full_settings;
  full_settings.spp = o.spp;
  full_settings.seed = o.seed;
  full_settings.pixel_filter = o.pixel_filter;
  std::unique_ptr<foveation::FoveatedView> foveated;
  double precompute_ms = 0.0;
  foveation::FoveaPattern fov_display_pattern = foveation::FoveaPattern::kPixelGrid;
  if (run_foveated) {
    std::string bad;
    std::optional<std::filesystem::path> cache;
    if (!o.cache_dir.empty()) cache = std::filesystem::path(o.cache_dir);
    const auto t_tables = std::chrono::steady_clock::now();
    auto tables = load_foveated_tables(o, view, cache, executor,
                                       [&](const std::string& m) { err << "fovea render: " << m << "\n"; }, &bad);
    if (!tables) {
      err << "fovea render: " << bad << "\n";
      return 1;
    }
    precompute_ms = ms_since(t_tables);
    fov_display_pattern = tables->key.display.fovea_pattern;
    foveated = std::make_unique<foveation::FoveatedView>(std::move(tables), taa_view_settings(o.taa, o.spp, o.seed, o.pixel_filter,
                                                                                              o.taa_mean_while_young));
  }
  FrameTimes full_times, fov_times;
  std::vector<double> tile_ms;  // full mode: per-tile time summed over frames
  TileGrid grid;                // full mode's tiles
  engine::RayCounts full_rays, fov_rays;
  uint64_t fov_points = 0;
  for (int frame = 0; frame < o.frames; ++frame) {
    if (run_full) {
      const engine::RayCounts before = tracer->counts();
      const engine::RenderResult rr =
          engine::render_full(&foveart_engine_trace_rays, tracer.get(), view, full_settings, &full, executor);
      if (rr.status != FOVEART_RESULT_SUCCESS) {
        err << "fovea render: engine callback failed with status " << rr.status << "\n";
        return 1;
      }
      full_times.add(rr.trace_ms, 0.0);
      if (frame == 0) {
        full_rays = minus(tracer->counts(), before);
        grid = {view.width_px, view.height_px, rr.tile_width_px, rr.tile_height_px, rr.tiles_x};
        tile_ms.assign(rr.tile_ms.size(), 0.0);
      }
      for (size_t t = 0; t < tile_ms.size(); ++t) tile_ms[t] += rr.tile_ms[t];
    }
    if (run_foveated) {
      const engine::RayCounts before = tracer->counts();
      foveation::FrameRequest request;
      request.view = view;
      request.gaze_px = gaze;
      request.frame_index = static_cast<uint64_t>(frame);
      const foveation::FrameResult fr = foveated->render(request, &foveart_engine_trace_rays, tracer.get(), executor);
      if (!fr.ok()) {
        err << "fovea render: " << fr.message << "\n";
        return 1;
      }
      fov_times.add(fr.select_ms + fr.trace_ms, fr.reconstruct_ms, fr.select_ms);
      if (frame == 0) {
        fov_rays = minus(tracer->counts(), before);
        fov_points = fr.points;
      }
    }
  }
  report["frames"] = o.frames;
  if (run_full)
    report["full"] = {{"rays", rays_json(full_rays)}, {"lanes_per_packet", lanes_per_packet(full_rays)},
                      {"trace_ms", full_times.median_trace_ms()}, {"reconstruct_ms", 0.0},
                      {"total_ms", full_times.median_total_ms()}, {"frames_total_ms", full_times.total_ms}};
  if (run_foveated) {
    report["points"] = fov_points;
    report["foveated"] = {{"rays", rays_json(fov_rays)}, {"lanes_per_packet", lanes_per_packet(fov_rays)},
                          {"method", o.method}, {"k", reconstruction_k(o)}, {"scale", o.scale}, {"taa", o.taa},
                          {"pattern", foveation::fovea_pattern_name(fov_display_pattern)},
                          {"precompute_ms", precompute_ms}, {"trace_ms", fov_times.median_trace_ms()},
                          {"samples_ms", fov_times.median_samples_ms()},
                          {"reconstruct_ms", fov_times.median_reconstruct_ms()},
                          {"total_ms", fov_times.median_total_ms()}, {"frames_total_ms", fov_times.total_ms}};
  }
  std::optional<foveation::EccentricityMap> ecc;
  const auto ecc_map = [&]() -> const foveation::EccentricityMap& {
    if (!ecc) ecc = foveation::eccentricity_map(view, gaze);
    return *ecc;
  };
  if (!o.reference_spp.empty() || !o.reference_file.empty()) {
    foveation::ImageRgb reference;
    Json ref_json;
    if (!o.reference_file.empty()) {
      if (std::string e = read_pfm(o.reference_file, &reference); !e.empty()) {
        err << "fovea render: --reference: " << e << "\n";
        return 1;
      }
      if (reference.width_px != int(view.width_px) || reference.height_px != int(view.height_px)) {
        err << "fovea render: --reference: " << o.reference_file << " is " << reference.width_px << "x"
            << reference.height_px << ", the view is " << view.width_px << "x" << view.height_px << "\n";
        return 1;
      }
      ref_json = {{"source", "file"}, {"file", o.reference_file}};
    } else {
      ReferenceOptions ro;
      if (o.reference_spp != "auto") ro.spp = std::stoi(o.reference_spp);
      ro.baseline_spp = std::max(16, o.spp);  // far below this render and the price list's best full render
      ro.seed = o.seed;
      ro.pixel_filter = o.pixel_filter;
      ro.cache_dir = !o.reference_cache.empty() ? o.reference_cache
                     : !o.cache_dir.empty()      ? (std::filesystem::path(o.cache_dir) / "reference").string()
                                                 : std::string();
      std::string bad;
      std::optional<Reference> ref = converged_reference(
          &foveart_engine_trace_rays, tracer.get(), rendered_scene_hash(*tracer), view, gaze, ro, executor,
          [&](const std::string& m) { err << "fovea render: " << m << "\n"; }, &bad);
      if (!ref) {
        err << "fovea render: " << bad << "\n";
        return 1;
      }
      Json residual = Json::array();
      for (double mse : ref->residual_mse(ecc_map())) residual.push_back(number_or_null_json(foveation::psnr_of_mse(mse)));
      ref_json = {{"source", "converged full render"}, {"spp", ref->spp}, {"spp_tried", ref->tried_spp},
                  {"converged", ref->converged}, {"db_per_doubling", ref->db_per_doubling},
                  {"from_cache", ref->from_cache}, {"cache_file", ref->cache_file}, {"render_ms", ref->render_ms},
                  {"residual_psnr", residual}};
      reference = std::move(ref->image);
    }
    const foveation::ImageRgb reference_display = foveation::display_encode(reference);
    Json against = {{"reference", ref_json}};
    if (run_full)
      against["full"] = comparison_json(foveation::compare_images(reference_display, foveation::display_encode(full), ecc_map()));
    if (run_foveated)
      against["foveated"] = comparison_json(
          foveation::compare_images(reference_display, foveation::display_encode(foveated->image()), ecc_map()));
    report["errors_against_reference"] = against;
  }
  const double full_total = run_full ? full_times.median_total_ms() : 0.0;
  const double fov_total = run_foveated ? fov_times.median_total_ms() : 0.0;
  if (o.mode == "both") {
    report["speedup"] = fov_total > 0.0 ? full_total / fov_total : 0.0;
    // What the scene alone allows (content_speedup.hpp), and the rest: the
    // foveation's own cost relative to the rays it traces.
    const uint32_t tiles_y = grid.tiles_x ? static_cast<uint32_t>(tile_ms.size() / grid.tiles_x) : 0;
    const foveation::GazeMapping mapping =
        foveation::map_gaze(static_cast<int>(view.width_px), static_cast<int>(view.height_px), gaze);
    const double content_bound = content_speedup(
        grid, tile_ms,
        foveation::points_per_tile(foveated->tables().points, mapping, grid.tile_w_px, grid.tile_h_px, grid.tiles_x,
                                   tiles_y));
    report["content_speedup"] = content_bound;
    report["overhead_fraction"] = full_total > 0.0 ? fov_total * content_bound / full_total - 1.0 : 0.0;
    // Agreement of the two images (both carry their own noise), not accuracy: see errors_against_reference.
    const foveation::ImageComparison cmp = foveation::compare_images(
        foveation::display_encode(full), foveation::display_encode(foveated->image()), ecc_map());
    const Json c = comparison_json(cmp);
    report["rings_compared_against"] = "full render at the same rays per pixel";
    report["psnr"] = c["psnr"];
    report["ssim"] = c["ssim"];
    report["csf_rmse"] = c["csf_rmse"];
    report["rings"] = c["rings"];
  }
  if (!o.out_prefix.empty()) {
    Json files = Json::array();
    auto save = [&](const foveation::ImageRgb* img, const char* suffix) {
      if (img == nullptr || img->rgb.empty()) return true;
      const std::string path = o.out_prefix + suffix;
      if (std::string e = toolkit::write_png(path, *img, toolkit::PngValues::linear); !e.empty()) {
        err << "fovea render: " << e << "\n";
        return false;
      }
      files.push_back(path);
      return true;
    };
    if (!save(&full, "_full.png") || !save(foveated ? &foveated->image() : nullptr, "_foveated.png")) return 1;
    report["images"] = files;
  }
  if (o.json) {
    out << report.dump(2) << "\n";
  } else {
    out << "scene " << report["scene"].get<std::string>() << " (" << report["triangles"] << " triangles, "
        << report["effects"].get<std::string>() << "), " << view.width_px << "x" << view.height_px << ", spp " << o.spp << "\n";
    for (const char* mode : {"full", "foveated"}) {
      if (!report.contains(mode)) continue;
      const Json& m = report[mode];
      out << mode << ": " << m["total_ms"].get<double>() << " ms (trace " << m["trace_ms"].get<double>()
          << ", reconstruct " << m["reconstruct_ms"].get<double>() << "); rays primary " << m["rays"]["primary"]
          << ", shadow " << m["rays"]["shadow"] << ", reflection " << m["rays"]["reflection"] << ", refraction "
          << m["rays"]["refraction"] << "\n";
    }
    if (report.contains("speedup"))
      out << "speedup " << report["speedup"].get<double>() << ", PSNR " << report["psnr"] << " dB, SSIM "
          << report["ssim"].get<double>() << "\n";
  }
  return 0;
}

}  // namespace foveart::tools

namespace {

// "X,Y" -> two numbers.
template <typename Vec>
std::string parse_pair(const std::string& text, Vec* out) {
  std::istringstream in(text);
  char comma = 0;
  typename Vec::value_type a{}, b{};
  if (!(in >> a >> comma >> b) || comma != ',' || !(in >> std::ws).eof()) return "expected two numbers X,Y";
  *out = Vec(a, b);
  return "";
}

// "A,B,C,..." -> exactly N finite numbers.
template <std::size_t N>
std::string parse_list(const std::string& text, std::array<double, N>* out) {
  std::istringstream in(text);
  for (std::size_t i = 0; i < N; ++i) {
    char comma = ',';
    if ((i > 0 && !(in >> comma)) || comma != ',' || !(in >> (*out)[i]))
      return "expected " + std::to_string(N) + " comma-separated numbers";
    if (!std::isfinite((*out)[i])) return "values must be finite";
  }
  if (!(in >> std::ws).eof()) return "expected " + std::to_string(N) + " comma-separated numbers";
  return "";
}

}  // namespace

void register_render(CLI::App& app) {
  auto opts = std::make_shared<foveart::tools::RenderOptions>();
  auto gaze = std::make_shared<std::string>();
  auto size = std::make_shared<std::string>();
  auto fov = std::make_shared<std::string>();
  auto pose = std::make_shared<std::string>();
  CLI::App* cmd = app.add_subcommand("render", "Render a glTF scene with the sample engine (full, foveated or both)");
  cmd->add_option("--scene", opts->scene, "glTF/GLB file, or 'default' for the built-in scene")->capture_default_str();
  cmd->add_option("--preset", opts->preset, "Display preset")->capture_default_str();
  cmd->add_option("--eye", opts->eye, "left or right")->capture_default_str();
  cmd->add_option("--gaze", *gaze, "Gaze X,Y in pixels of the eye image (default: centre)");
  cmd->add_option("--mode", opts->mode, "full, foveated or both")->capture_default_str();
  cmd->add_option("--spp", opts->spp, "Rays per pixel (full) or per point (foveated)")->capture_default_str();
  cmd->add_option("--method", opts->method, "Reconstruction: nn, msm or rbf-mq")->capture_default_str();
  cmd->add_option("--k", opts->k, "Neighbours for the reconstruction (msm, rbf-mq; default 5; nn uses 1)");
  cmd->add_option("--scale", opts->scale, "Point density scale (thesis 4.1)")->capture_default_str();
  cmd->add_option("--pattern", opts->pattern,
                  "Fovea sampling: pixel-grid (default) or thesis (Poisson everywhere; the thesis preset's)");
  cmd->add_option("--frames", opts->frames,
                  "Frames per mode, modes interleaved; times are each mode's median frame (with --motion: the "
                  "sequence's frames)")
      ->capture_default_str();
  cmd->add_option("--threads", opts->threads, "Tracing threads (0 = all cores)")->capture_default_str();
  cmd->add_option("--size", *size, "Override the per-eye size W,H (same horizontal FOV)");
  cmd->add_option("--fov", *fov, "Exact view frustum L,R,U,D: XrFovf angles in degrees (point set from the R-L span)");
  cmd->add_option("--pose", *pose, "Exact eye pose in scene space px,py,pz,qx,qy,qz,qw (metres, unit quaternion)");
  cmd->add_option("--out", opts->out_prefix, "Write PREFIX_full.png / PREFIX_foveated.png");
  cmd->add_option("--cache", opts->cache_dir, "Directory for cached point sets and neighbour tables");
  cmd->add_option("--seed", opts->seed, "Seed of point set and jitter")->capture_default_str();
  cmd->add_option("--without", opts->without,
                  "Leave these effects out of the scene, the reference too: shadows, reflection, refraction, "
                  "textures, comma-separated (default: every effect the scene calls for)");
  foveart::fovea::add_pixel_filter_option(cmd, &opts->pixel_filter);
  cmd->add_option("--reference-spp", opts->reference_spp,
                  "Errors against a converged full render: 'auto' (convergence check) or rays per pixel N");
  cmd->add_option("--reference", opts->reference_file, "Errors against this linear-RGB PFM of the view");
  cmd->add_option("--reference-cache", opts->reference_cache, "Reference cache directory (default: CACHE/reference)");
  cmd->add_option("--taa", opts->taa,
                  "TAA of the foveated frames: off, restart (on every pose change), reproject (follows the head), "
                  "cache (the traced rays kept in a render cache), cache-kept (its rays kept through "
                  "saccades); with --motion a list, e.g. off,restart,reproject")
      ->capture_default_str();
  cmd->add_flag("--taa-mean-while-young", opts->taa_mean_while_young,
                "TAA: the k-th frame since a restart weighs max(1/k, alpha), the mean of a young history "
                "(the layer's \"taa_mean_while_young\"); default: alpha from the second frame on");
  cmd->add_option("--motion", opts->motion,
                  "Render --frames frames of a head and gaze motion: 'builtin' or a CSV file "
                  "(time_s,qx,qy,qz,qw,px,py,pz,gx,gy,gz,valid[,saccade])");
  auto start_s = std::make_shared<double>(0.0);
  auto fps = std::make_shared<double>(70.0);
  CLI::Option* start_opt = cmd->add_option("--start-s", *start_s, "With --motion: time of the first frame (s), default 0");
  CLI::Option* fps_opt = cmd->add_option("--fps", *fps, "With --motion: frames per second, default 70");
  cmd->add_flag("--json", opts->json, "Print the report as JSON");
  cmd->callback([opts, gaze, size, fov, pose, start_s, fps, start_opt, fps_opt] {
    if (start_opt->count() > 0) opts->start_s = *start_s;
    if (fps_opt->count() > 0) opts->fps = *fps;
    if (!gaze->empty()) {
      glm::vec2 g;
      if (std::string e = parse_pair(*gaze, &g); !e.empty()) throw CLI::ValidationError("--gaze", e);
      if (!std::isfinite(g.x) || !std::isfinite(g.y)) throw CLI::ValidationError("--gaze", "must be finite");
      opts->gaze_px = g;
    }
    if (!size->empty()) {
      glm::ivec2 s;
      if (std::string e = parse_pair(*size, &s); !e.empty()) throw CLI::ValidationError("--size", e);
      opts->size_px = s;
    }
    if (!fov->empty()) {
      std::array<double, 4> f{};
      if (std::string e = parse_list(*fov, &f); !e.empty()) throw CLI::ValidationError("--fov", e);
      opts->fov_deg = f;
    }
    if (!pose->empty()) {
      std::array<double, 7> p{};
      if (std::string e = parse_list(*pose, &p); !e.empty()) throw CLI::ValidationError("--pose", e);
      opts->pose = p;
    }
    const int code = foveart::tools::run_render(*opts, std::cout, std::cerr);
    if (code != 0) throw CLI::RuntimeError(code);
  });
}
