// `fovea render`: full-resolution and/or foveated rendering of a glTF scene with
// the sample engine; JSON report of rays per effect, times, the speedup and the
// content bound. The foveated
// frame is foveation::FoveatedView, the one the OpenXR layer runs. --engine gpu
// answers the same callback with the GPU sample engine
// (gpu_engine::CallbackAdapter: one device round trip per batch, so its times
// include the transfers); reconstruction stays on the CPU either way.
#include "cmd_render.hpp"


#include "content_speedup.hpp"
#include "rays_map.hpp"
#include <render_view/display_options.hpp>
#include <render_view/render_cli.hpp>
#include <metrics/comparison_json.hpp>

#include <engine/gltf_loader.hpp>
#include <engine/render.hpp>
#include <engine/tracer.hpp>
#include <gpu_engine/callback_adapter.hpp>

#include <foveation/display_model.hpp>
#include <foveation/elapsed.hpp>
#include <foveation/executor.hpp>
#include <foveation/foveated_view.hpp>

#include <toolkit/image_io.hpp>
#include <toolkit/outputs.hpp>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <functional>
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

namespace foveart::fovea {
namespace {

using Json = nlohmann::ordered_json;

using foveation::ms_since;

Json rays_json(const engine::RayCounts& c) {
  return Json{{"primary", c.primary}, {"shadow", c.shadow}, {"reflection", c.reflection}, {"refraction", c.refraction}};
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

// Whether frame i of n counts in a speedup: the first (first touches of the
// images and caches) is left out when there are three or more.
bool timed_frame(std::size_t i, std::size_t n) { return i > 0 || n < 3; }

// The median over interleaved frame pairs of num[i] / den[i]: each pair saw the
// machine in the same state, so a slow spell cancels instead of landing on one
// side of a ratio of medians. Timed frames only (timed_frame).
double median_pair_ratio(const std::vector<double>& num, const std::vector<double>& den) {
  std::vector<double> r;
  const std::size_t n = std::min(num.size(), den.size());
  for (std::size_t i = 0; i < n; ++i)
    if (timed_frame(i, num.size()) && den[i] > 0.0) r.push_back(num[i] / den[i]);
  if (r.empty()) return 0.0;
  std::sort(r.begin(), r.end());
  return r.size() % 2 == 1 ? r[r.size() / 2] : 0.5 * (r[r.size() / 2 - 1] + r[r.size() / 2]);
}

// Who answers the rays: the CPU engine (engine::Tracer) or the GPU engine behind
// the same callback (gpu_engine::CallbackAdapter).
struct RenderEngine {
  std::unique_ptr<engine::Tracer> cpu;
  std::unique_ptr<gpu_engine::CallbackAdapter> gpu;

  FoveartTraceRaysFn fn() const { return gpu ? &foveart_gpu_engine_trace_rays : &foveart_engine_trace_rays; }
  void* user() const { return gpu ? static_cast<void*>(gpu.get()) : static_cast<void*>(cpu.get()); }
  const engine::Scene& scene() const { return gpu ? gpu->scene() : cpu->scene(); }
  engine::Effects effects() const { return gpu ? gpu->effects() : cpu->effects(); }
  engine::Effects scene_effects() const { return gpu ? gpu->scene_effects() : cpu->scene_effects(); }
  engine::RayCounts counts() const { return gpu ? gpu->counts() : cpu->counts(); }
};

constexpr const char* kRenderWho = "fovea render: ";

// The engine's failing status as a message, with the GPU engine's own words when it has them.
std::string engine_failure(const RenderEngine& eng, std::int32_t status, const std::string& what) {
  std::string m = what + " failed with status " + std::to_string(status);
  if (eng.gpu && !eng.gpu->last_error().empty()) m += " (" + eng.gpu->last_error() + ")";
  return m;
}

// Checks before any work: the options and the images' files (--out). False and *error.
[[nodiscard]] bool check_options(const render_view::RenderOptions& o, std::string* error) {
  if (o.engine != "cpu" && o.engine != "gpu") {
    *error = "--engine must be cpu or gpu, not \"" + o.engine + "\"";
    return false;
  }
  if (!render_view::check_render_options(o, error)) return false;
  for (const char* suffix : {"_full.png", "_foveated.png", "_rays.png"})
    if (!o.out_prefix.empty() && !toolkit::check_writable_file(o.out_prefix + suffix, error)) {
      *error = "--out: " + *error;
      return false;
    }
  return true;
}

// The scene loaded into the engine asked for; false and *error.
[[nodiscard]] bool load_engine(const render_view::RenderOptions& o, std::ostream& err, RenderEngine* eng,
                               Json* report, std::string* error) {
  auto t0 = std::chrono::steady_clock::now();
  engine::LoadResult loaded = engine::load_scene(o.scene);
  if (!loaded.ok()) {
    *error = loaded.error;
    return false;
  }
  (*report)["load_ms"] = ms_since(t0);
  for (const std::string& w : loaded.scene->warnings) err << kRenderWho << "warning: " << w << "\n";
  t0 = std::chrono::steady_clock::now();
  const engine::TracerOptions cpu_options = render_view::render_tracer_options(o);
  if (o.engine == "gpu") {
    gpu_engine::CallbackAdapterOptions gpu_options;
    gpu_options.tracer.max_depth = cpu_options.max_depth;
    gpu_options.tracer.allowed = cpu_options.allowed;
    eng->gpu = gpu_engine::CallbackAdapter::create(std::move(*loaded.scene), gpu_options, error);
    if (!eng->gpu) *error = "--engine gpu: " + *error;
  } else {
    eng->cpu = engine::Tracer::create(std::move(*loaded.scene), cpu_options, error);
  }
  (*report)["build_ms"] = ms_since(t0);
  return eng->gpu || eng->cpu;
}

// What is rendered: the scene, the engine and the view.
void add_view_json(const render_view::RenderOptions& o, const RenderEngine& eng, const FoveartEyeView& view,
                   glm::vec2 gaze, Json& report) {
  report["scene"] = eng.scene().source;
  report["triangles"] = eng.scene().mesh.triangles.size();
  report["effects"] = engine::to_string(eng.effects());
  report["engine"] = o.engine;
  // The GPU engine's Vulkan device; its times include a device round trip per batch.
  if (eng.gpu) report["gpu_device"] = eng.gpu->device_name();
  report["eye"] = o.eye;
  report["width"] = view.width_px;
  report["height"] = view.height_px;
  report["gaze"] = {gaze.x, gaze.y};
  report["fov_deg"] = render_view::fov_deg(view);
  report["pose"] = {view.position_m[0],        view.position_m[1],        view.position_m[2],
                    view.orientation_xyzw[0], view.orientation_xyzw[1], view.orientation_xyzw[2],
                    view.orientation_xyzw[3]};
  report["rays_per_point"] = o.rays_per_point;
  report["pixel_filter"] = foveation::pixel_filter_name(o.pixel_filter);
}

// The foveated view: its tables (from the cache or built: precompute_ms) and the product's temporal mode.
struct Foveated {
  std::unique_ptr<foveation::FoveatedView> view;
  double precompute_ms = 0.0;
};

[[nodiscard]] bool make_foveated(const render_view::RenderOptions& o, const FoveartEyeView& view,
                                 const foveation::DisplayTransform& display, foveation::Executor& executor,
                                 std::ostream& err, Foveated* f, std::string* error) {
  std::optional<std::filesystem::path> cache;
  if (!o.cache_dir.empty()) cache = std::filesystem::path(o.cache_dir);
  const auto t0 = std::chrono::steady_clock::now();
  auto tables = render_view::load_foveated_tables(
      o, view, cache, executor, [&](const std::string& m) { err << kRenderWho << m << "\n"; }, error);
  if (!tables) return false;
  f->precompute_ms = ms_since(t0);
  foveation::ViewSettings settings = render_view::foveated_view_settings(o);
  settings.content_density.exposure = display.exposure;
  f->view = std::make_unique<foveation::FoveatedView>(std::move(tables), settings);
  return true;
}

// What the frames measured: per mode its times and the rays of its first frame; the full
// render's image, per-tile time and tiles (content_speedup.hpp); the foveated view's points.
struct Frames {
  FrameTimes full_times, fov_times;
  foveation::ImageRgb full;
  std::vector<double> tile_ms;  // per tile, summed over the timed frames
  TileGrid grid;
  engine::RayCounts full_rays, fov_rays;
  uint64_t fov_points = 0;
  uint64_t fov_points_thinned = 0;
  std::vector<foveation::DensityCost> fov_density;  // per frame, content-aware density's stages
  std::vector<std::uint64_t> fov_cached_rays;       // per frame, the render cache's kept rays after it
};

[[nodiscard]] bool render_full_frame(const render_view::RenderOptions& o, const RenderEngine& eng,
                                     const FoveartEyeView& view, int frame, foveation::Executor& executor, Frames* f,
                                     std::string* error) {
  engine::RenderSettings settings;
  settings.spp = o.rays_per_point;
  settings.seed = o.seed;
  settings.pixel_filter = o.pixel_filter;
  const engine::RayCounts before = eng.counts();
  const engine::RenderResult rr = engine::render_full(eng.fn(), eng.user(), view, settings, &f->full, executor);
  if (rr.status != FOVEART_RESULT_SUCCESS) {
    *error = engine_failure(eng, rr.status, "engine callback");
    return false;
  }
  f->full_times.add(rr.trace_ms, 0.0);
  if (frame == 0) {
    f->full_rays = eng.counts() - before;
    f->grid = {view.width_px, view.height_px, rr.tile_width_px, rr.tile_height_px, rr.tiles_x};
    f->tile_ms.assign(rr.tile_ms.size(), 0.0);
  }
  if (timed_frame(std::size_t(frame), std::size_t(o.frames)))  // as the speedups it is compared with
    for (size_t t = 0; t < f->tile_ms.size(); ++t) f->tile_ms[t] += rr.tile_ms[t];
  return true;
}

[[nodiscard]] bool render_foveated_frame(const render_view::RenderOptions& o, const RenderEngine& eng,
                                         const FoveartEyeView& view, glm::vec2 gaze, int frame,
                                         foveation::Executor& executor, foveation::FoveatedView& foveated, Frames* f,
                                         std::string* error) {
  const engine::RayCounts before = eng.counts();
  foveation::FrameRequest request;
  request.view = view;
  request.gaze_px =
      o.gaze_px_per_frame.empty()
          ? gaze
          : o.gaze_px_per_frame[std::min<std::size_t>(std::size_t(frame), o.gaze_px_per_frame.size() - 1)];
  request.frame_index = o.first_frame + static_cast<uint64_t>(frame);
  const foveation::FrameResult fr = foveated.render(request, eng.fn(), eng.user(), executor);
  if (!fr.ok()) {
    *error = fr.message;
    if (eng.gpu && !eng.gpu->last_error().empty()) *error += " (" + eng.gpu->last_error() + ")";
    return false;
  }
  // The fixed part: reconstruction and the temporal history.
  f->fov_times.add(fr.select_ms + fr.trace_ms, fr.reconstruct_ms + fr.temporal_ms, fr.select_ms);
  // The last frame's: content-aware density thins from the second frame on.
  f->fov_rays = eng.counts() - before;
  f->fov_points = fr.points;
  f->fov_points_thinned = fr.points_thinned;
  f->fov_density.push_back(fr.density);
  f->fov_cached_rays.push_back(foveated.cached_rays());
  return true;
}

// Each mode renders o.frames frames, the modes interleaved (full, foveated,
// full, ...) so that a slow spell of the machine falls on both; the report
// gives each mode's median frame. The first frame of each pays for first
// touches (fresh image memory, the mmap-ed neighbour table, cold caches) and
// stays in frames_total_ms.
[[nodiscard]] bool render_frames(const render_view::RenderOptions& o, const RenderEngine& eng,
                                 const FoveartEyeView& view, glm::vec2 gaze, foveation::Executor& executor,
                                 foveation::FoveatedView* foveated, Frames* f, std::string* error) {
  for (int frame = 0; frame < o.frames; ++frame) {
    if (o.mode != "foveated" && !render_full_frame(o, eng, view, frame, executor, f, error)) return false;
    if (foveated && !render_foveated_frame(o, eng, view, gaze, frame, executor, *foveated, f, error)) return false;
  }
  return true;
}

// The two modes' times and rays; Embree's packet fill (the GPU engine has no packets: null).
void add_modes_json(const render_view::RenderOptions& o, const RenderEngine& eng, const Frames& f,
                    const Foveated& fov, const foveation::DisplayTransform& display, Json& report) {
  const auto packets_json = [&](const engine::RayCounts& c) {
    return eng.gpu ? Json(nullptr) : Json(lanes_per_packet(c));
  };
  report["frames"] = o.frames;
  if (fov.view) report["first_frame"] = o.first_frame;
  if (o.mode != "foveated")
    report["full"] = {{"rays", rays_json(f.full_rays)}, {"lanes_per_packet", packets_json(f.full_rays)},
                      {"trace_ms", f.full_times.median_trace_ms()}, {"reconstruct_ms", 0.0},
                      {"total_ms", f.full_times.median_total_ms()}, {"frames_total_ms", f.full_times.total_ms},
                      {"white_clipped_fraction", foveation::white_clipped_fraction(f.full, display)}};
  if (!fov.view) return;
  const foveation::DensityCost& density = f.fov_density[f.fov_times.median_frame()];
  report["points"] = f.fov_points;
  report["points_thinned"] = f.fov_points_thinned;
  report["foveated"] = {{"rays", rays_json(f.fov_rays)},
                        {"lanes_per_packet", packets_json(f.fov_rays)},
                        {"interpolation", o.interpolation},
                        {"k", render_view::reconstruction_k(o)},
                        {"density_scale", o.density_scale},
                        {"content_contrast", o.content_contrast},
                        {"content_rays", render_view::content_rays_of(o)},
                        {"content_rays_doubling_deg", render_view::content_rays_doubling_of(o)},
                        {"density_ms", density.total_ms()},  // the median frame's, as its stages
                        {"density_stages_ms", {{"levels", density.levels_ms}, {"test", density.test_ms},
                                               {"observe", density.observe_ms}, {"fill", density.fill_ms}}},
                        {"temporal", foveation::temporal_mode_name(o.temporal)},
                        {"pattern", foveation::fovea_pattern_name(fov.view->tables().key.display.fovea_pattern)},
                        {"precompute_ms", fov.precompute_ms},
                        {"trace_ms", f.fov_times.median_trace_ms()},
                        {"samples_ms", f.fov_times.median_samples_ms()},
                        {"reconstruct_ms", f.fov_times.median_reconstruct_ms()},
                        {"total_ms", f.fov_times.median_total_ms()},
                        {"frames_total_ms", f.fov_times.total_ms},
                        {"frames_cached_rays", f.fov_cached_rays},
                        {"white_clipped_fraction", foveation::white_clipped_fraction(fov.view->image(), display)}};
}

// --mode both: the speedup, what the content allows (content_speedup.hpp), the speedup's parts,
// and how the two images agree per ring.
void add_speedup_json(const FoveartEyeView& view, glm::vec2 gaze, const Frames& f,
                      const foveation::FoveatedView& foveated, const foveation::DisplayTransform& display,
                      Json& report) {
  const double full_total = f.full_times.median_total_ms(), fov_total = f.fov_times.median_total_ms();
  report["speedup"] = median_pair_ratio(f.full_times.total_ms, f.fov_times.total_ms);
  // What the scene alone allows, and the rest: the foveation's own cost relative to the rays it traces.
  const uint32_t tiles_y = f.grid.tiles_x ? static_cast<uint32_t>(f.tile_ms.size() / f.grid.tiles_x) : 0;
  const foveation::GazeMapping mapping =
      foveation::map_gaze(static_cast<int>(view.width_px), static_cast<int>(view.height_px), gaze);
  const double content_bound = content_speedup(
      f.grid, f.tile_ms,
      foveation::points_per_tile(foveated.tables().points, mapping, f.grid.tile_w_px, f.grid.tile_h_px,
                                 f.grid.tiles_x, tiles_y));
  report["content_speedup"] = content_bound;
  report["overhead_fraction"] = full_total > 0.0 ? fov_total * content_bound / full_total - 1.0 : 0.0;
  // The speedup in its two parts: the sparse trace (selection + rays + trace),
  // which scales with the scene's cost, and the fixed per-frame cost of
  // reconstruction and history, which does not. Foveation pays while the full
  // frame costs more than fixed * s / (s - 1), s the trace's own speedup.
  const double fixed = f.fov_times.median_reconstruct_ms();
  const double trace_speedup = median_pair_ratio(f.full_times.total_ms, f.fov_times.trace_ms);
  report["speedup_parts"] = {
      {"trace_speedup", trace_speedup},
      {"trace_of_content_speedup", content_bound > 0.0 ? trace_speedup / content_bound : 0.0},
      {"fixed_ms", fixed},
      {"fixed_share_of_foveated", fov_total > 0.0 ? fixed / fov_total : 0.0},
      {"breakeven_full_ms", trace_speedup > 1.0 ? Json(fixed * trace_speedup / (trace_speedup - 1.0)) : Json(nullptr)}};
  // Agreement of the two images (both carry their own noise), not accuracy against the truth: that is
  // the lab's (`fovea-eval accuracy`, against a converged reference).
  const metrics::ImageComparison cmp = metrics::compare_images(
      metrics::display_encode(f.full, display.exposure), metrics::display_encode(foveated.image(), display.exposure),
      metrics::eccentricity_map(view, gaze));
  const Json c = metrics::comparison_json(cmp);
  report["rings_compared_against"] = "full render at the same rays per pixel";
  report["psnr"] = c["psnr"];
  report["ssim"] = c["ssim"];
  report["csf_rmse"] = c["csf_rmse"];
  report["rings"] = c["rings"];
}

// --out PREFIX: PREFIX_full.png and PREFIX_foveated.png through the display transform; with a
// CPU trace, PREFIX_rays.png: the last foveated frame's rays per point (rays_map.hpp).
[[nodiscard]] bool write_images(const render_view::RenderOptions& o, const Frames& f, const Foveated& fov,
                                const foveation::DisplayTransform& display, Json* files, std::string* error) {
  *files = Json::array();
  for (const auto& [img, suffix] : {std::pair{&f.full, "_full.png"},
                                    std::pair{fov.view ? &fov.view->image() : nullptr, "_foveated.png"}}) {
    if (img == nullptr || img->rgb.empty()) continue;
    const std::string path = o.out_prefix + suffix;
    if (!toolkit::write_png(path, *img, display, error)) return false;
    files->push_back(path);
  }
  if (!fov.view || fov.view->image().rgb.empty() || fov.view->hand_off().traced == nullptr) return true;
  const std::string path = o.out_prefix + "_rays.png";
  const foveation::ImageRgb map =
      rays_map(fov.view->tables(), fov.view->hand_off(), fov.view->image(), display, unsigned(o.rays_per_point));
  if (!toolkit::write_png(path, map, toolkit::PngValues::display, error)) return false;
  files->push_back(path);
  return true;
}

void print_text(const render_view::RenderOptions& o, const RenderEngine& eng, const FoveartEyeView& view,
                const foveation::DisplayTransform& display, const Json& report, std::ostream& out) {
  out << "scene " << report["scene"].get<std::string>() << " (" << report["triangles"] << " triangles, "
      << report["effects"].get<std::string>() << "), " << view.width_px << "x" << view.height_px << ", rays per point "
      << o.rays_per_point << "\n";
  out << "engine " << o.engine;
  if (eng.gpu)
    out << " (" << eng.gpu->device_name() << ", " << eng.gpu->backend_name()
        << "; each batch a device round trip, times include transfers)";
  out << "\n";
  for (const char* mode : {"full", "foveated"}) {
    if (!report.contains(mode)) continue;
    const Json& m = report[mode];
    out << mode << ": " << m["total_ms"].get<double>() << " ms (trace " << m["trace_ms"].get<double>()
        << ", reconstruct " << m["reconstruct_ms"].get<double>() << "); rays primary " << m["rays"]["primary"]
        << ", shadow " << m["rays"]["shadow"] << ", reflection " << m["rays"]["reflection"] << ", refraction "
        << m["rays"]["refraction"] << "\n";
  }
  if (report.contains("speedup")) {
    const Json& parts = report["speedup_parts"];
    out << "speedup " << report["speedup"].get<double>() << " (its content allows "
        << report["content_speedup"].get<double>() << "): the trace alone " << parts["trace_speedup"].get<double>()
        << ", plus a fixed " << parts["fixed_ms"].get<double>() << " ms of reconstruction and history; PSNR "
        << report["psnr"] << " dB, SSIM " << report["ssim"].get<double>() << "\n";
  }
  out << "display: exposure " << display.exposure << " (" << report["display"]["exposure_from"].get<std::string>()
      << "), tone map " << foveation::tone_map_name(display.tone_map) << "\n";
}

}  // namespace

int run_render(const render_view::RenderOptions& o, std::ostream& out, std::ostream& err) {
  std::string error;
  if (!check_options(o, &error)) {
    err << kRenderWho << error << "\n";
    return 2;
  }
  const auto fail = [&](const std::string& message) {
    err << kRenderWho << message << "\n";
    return 1;
  };
  Json report;
  RenderEngine eng;
  if (!load_engine(o, err, &eng, &report, &error)) return fail(error);
  const FoveartEyeView view = render_view::eye_view(o, eng.scene());
  const glm::vec2 gaze = o.gaze_px.value_or(
      glm::vec2(0.5f * static_cast<float>(view.width_px), 0.5f * static_cast<float>(view.height_px)));
  add_view_json(o, eng, view, gaze, report);
  foveation::Executor executor(static_cast<unsigned>(o.threads));  // every parallel stage of this run
  report["threads"] = executor.thread_count();
  const std::optional<foveation::DisplayTransform> display =
      render_view::render_display(o, eng.fn(), eng.user(), view, executor, &error);
  if (!display) return fail(error);
  report["display"] = {{"exposure", display->exposure},
                       {"exposure_from", o.exposure == "auto" ? "auto (pre-pass of the view)" : "--exposure"},
                       {"tone_map", foveation::tone_map_name(display->tone_map)}};
  report["pixels"] = static_cast<uint64_t>(view.width_px) * view.height_px;
  report["points"] = report["pixels"];  // full mode: one point per pixel; the visible points with foveated frames
  Foveated fov;
  Frames frames;
  if (o.mode != "full" && !make_foveated(o, view, *display, executor, err, &fov, &error)) return fail(error);
  if (!render_frames(o, eng, view, gaze, executor, fov.view.get(), &frames, &error)) return fail(error);
  add_modes_json(o, eng, frames, fov, *display, report);
  if (o.mode == "both") add_speedup_json(view, gaze, frames, *fov.view, *display, report);
  if (!o.out_prefix.empty()) {
    Json files;
    if (!write_images(o, frames, fov, *display, &files, &error)) return fail(error);
    report["images"] = files;
  }
  if (o.json)
    out << report.dump(2) << "\n";
  else
    print_text(o, eng, view, *display, report, out);
  return 0;
}

void register_render(CLI::App& app) {
  auto opts = std::make_shared<render_view::RenderOptions>();
  opts->content_rays.reset();  // the product's defaults, by the rays per point and the temporal mode
  opts->content_rays_doubling_deg.reset();
  auto gaze = std::make_shared<std::string>();
  auto pose = std::make_shared<std::string>();
  CLI::App* cmd = app.add_subcommand(
      "render", "Render a glTF scene with the sample engine, CPU or GPU (full, foveated or both)");
  const std::function<void()> parse_common = render_view::add_render_options(cmd, opts);
  render_view::add_temporal_option(cmd, opts);
  cmd->add_option("--gaze", *gaze,
                  "Gaze X,Y in pixels of the eye image (default: centre); X,Y;X,Y;...: the foveated frames' gazes in "
                  "turn, the last for the frames after");
  cmd->add_option("--first-frame", opts->first_frame,
                  "Index of the first foveated frame; with --temporal image or rays each frame's jitter seed is "
                  "--seed plus its index (default 1: the layer's first frame)")
      ->capture_default_str();
  cmd->add_option("--pose", *pose,
                  "Where the viewer stands, X,Y,Z (the head; the eye 32 mm aside), or an exact eye pose "
                  "px,py,pz,qx,qy,qz,qw (metres, unit quaternion; scene space)");
  // Accuracy against a converged reference is the lab's: these options say so instead of "not expected".
  for (const char* lab : {"--reference-spp", "--reference", "--reference-cache"})
    render_view::add_renamed_option(cmd, lab, std::string("fovea-eval accuracy ") + lab);
  cmd->add_option("--engine", opts->engine,
                  "Who traces the rays: cpu (the Embree sample engine) or gpu (the Vulkan compute sample engine "
                  "behind the same callback, a hardware GPU if any else lavapipe; each batch is a device round "
                  "trip, so its times include transfers). Reconstruction is on the CPU either way")
      ->capture_default_str();
  cmd->callback([opts, gaze, pose, parse_common] {
    parse_common();
    if (gaze->find(';') != std::string::npos) {
      std::stringstream list(*gaze);
      for (std::string item; std::getline(list, item, ';');)
        opts->gaze_px_per_frame.push_back(render_view::parse_gaze_option("--gaze", item));
      opts->gaze_px = opts->gaze_px_per_frame.back();
    } else if (!gaze->empty()) {
      opts->gaze_px = render_view::parse_gaze_option("--gaze", *gaze);
    }
    if (!pose->empty()) render_view::parse_pose_option("--pose", *pose, opts.get());
    const int code = run_render(*opts, std::cout, std::cerr);
    if (code != 0) throw CLI::RuntimeError(code);
  });
}

}  // namespace foveart::fovea
