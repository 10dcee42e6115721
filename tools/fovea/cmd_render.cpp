// `fovea render`: full-resolution and/or foveated rendering of a glTF scene with
// the sample engine; JSON report of rays per effect and times. The foveated
// frame is foveation::FoveatedView, the one the OpenXR layer runs. --engine gpu
// answers the same callback with the GPU sample engine
// (gpu_engine::CallbackAdapter: one device round trip per batch, so its times
// include the transfers); reconstruction stays on the CPU either way.
#include "cmd_render.hpp"
#include "taa_modes.hpp"

#include "content_speedup.hpp"
#include "render_cli.hpp"
#include "pfm.hpp"
#include <eval/reference.hpp>
#include <eval/render_metrics.hpp>

#include <engine/gltf_loader.hpp>
#include <engine/render.hpp>
#include <engine/tracer.hpp>
#include <gpu_engine/callback_adapter.hpp>

#include <foveation/display_model.hpp>
#include <foveation/elapsed.hpp>
#include <foveation/executor.hpp>
#include <foveation/foveated_view.hpp>

#include <toolkit/image_io.hpp>

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

#include <xxhash.h>

namespace foveart::tools {
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

constexpr double kPi = 3.14159265358979323846;

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
  // The reference cache's scene key: the CPU engine's rendered_scene_hash; the
  // GPU engine's references are its own (they agree per ray to ~1e-3, not exactly).
  uint64_t scene_hash() const {
    if (cpu) return rendered_scene_hash(*cpu);
    const uint64_t parts[3] = {scene_content_hash(scene()), static_cast<uint64_t>(effects().bits()),
                               0x6770755f656e67ull /* "gpu_eng" */};
    return XXH3_64bits(parts, sizeof(parts));
  }
};

}  // namespace

int run_render(const RenderOptions& o, std::ostream& out, std::ostream& err) {
  if (o.engine != "cpu" && o.engine != "gpu") {
    err << "fovea render: --engine must be cpu or gpu, not \"" << o.engine << "\"\n";
    return 2;
  }
  if (!o.motion.empty()) {
    err << "fovea render: one still view; a sequence over a motion is `fovea-eval motion`\n";
    return 2;
  }
  if (std::string bad; !check_render_options(o, &bad)) {
    err << "fovea render: " << bad << "\n";
    return 2;
  }
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
  RenderEngine eng;
  if (o.engine == "gpu") {
    const engine::TracerOptions cpu_options = render_tracer_options(o);
    gpu_engine::CallbackAdapterOptions gpu_options;
    gpu_options.tracer.max_depth = cpu_options.max_depth;
    gpu_options.tracer.allowed = cpu_options.allowed;
    eng.gpu = gpu_engine::CallbackAdapter::create(std::move(*loaded.scene), gpu_options, &error);
    if (!eng.gpu) {
      err << "fovea render: --engine gpu: " << error << "\n";
      return 1;
    }
  } else {
    eng.cpu = engine::Tracer::create(std::move(*loaded.scene), render_tracer_options(o), &error);
    if (!eng.cpu) {
      err << "fovea render: " << error << "\n";
      return 1;
    }
  }
  const double build_ms = ms_since(t0);
  const FoveartEyeView view = render_view(o, eng.scene());
  const glm::vec2 gaze = o.gaze_px.value_or(glm::vec2(0.5f * static_cast<float>(view.width_px),
                                                      0.5f * static_cast<float>(view.height_px)));
  const uint64_t pixels = static_cast<uint64_t>(view.width_px) * view.height_px;

  Json report;
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
  auto deg = [](float rad) { return static_cast<double>(rad) * 180.0 / kPi; };
  report["fov_deg"] = {deg(view.angle_left_rad), deg(view.angle_right_rad), deg(view.angle_up_rad),
                       deg(view.angle_down_rad)};
  report["pose"] = {view.position_m[0],        view.position_m[1],        view.position_m[2],
                    view.orientation_xyzw[0], view.orientation_xyzw[1], view.orientation_xyzw[2],
                    view.orientation_xyzw[3]};
  report["rays_per_point"] = o.rays_per_point;
  report["pixel_filter"] = foveation::pixel_filter_name(o.pixel_filter);
  foveation::Executor executor(static_cast<unsigned>(o.threads));  // every parallel stage of this run
  report["threads"] = executor.thread_count();
  std::string display_error;
  const std::optional<foveation::DisplayTransform> display = render_display(o, eng.fn(), eng.user(), view, executor, &display_error);
  if (!display) {
    err << "fovea render: " << display_error << "\n";
    return 1;
  }
  report["display"] = {{"exposure", display->exposure},
                       {"exposure_from", o.exposure == "auto" ? "auto (pre-pass of the view)" : "--exposure"},
                       {"tone_map", foveation::tone_map_name(display->tone_map)}};
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
  full_settings.spp = o.rays_per_point;
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
    foveated = make_taa_view(std::move(tables), o.taa, o.rays_per_point, o.seed, o.pixel_filter, o.taa_mean_while_young);
  }
  // Embree's packet fill; the GPU engine has no packets (null).
  const auto packets_json = [](const engine::RayCounts& c, const RenderEngine& e) {
    return e.gpu ? Json(nullptr) : Json(lanes_per_packet(c));
  };
  FrameTimes full_times, fov_times;
  std::vector<double> tile_ms;  // full mode: per-tile time summed over the timed frames
  TileGrid grid;                // full mode's tiles
  engine::RayCounts full_rays, fov_rays;
  uint64_t fov_points = 0;
  for (int frame = 0; frame < o.frames; ++frame) {
    if (run_full) {
      const engine::RayCounts before = eng.counts();
      const engine::RenderResult rr =
          engine::render_full(eng.fn(), eng.user(), view, full_settings, &full, executor);
      if (rr.status != FOVEART_RESULT_SUCCESS) {
        err << "fovea render: engine callback failed with status " << rr.status;
        if (eng.gpu && !eng.gpu->last_error().empty()) err << " (" << eng.gpu->last_error() << ")";
        err << "\n";
        return 1;
      }
      full_times.add(rr.trace_ms, 0.0);
      if (frame == 0) {
        full_rays = eng.counts() - before;
        grid = {view.width_px, view.height_px, rr.tile_width_px, rr.tile_height_px, rr.tiles_x};
        tile_ms.assign(rr.tile_ms.size(), 0.0);
      }
      if (timed_frame(std::size_t(frame), std::size_t(o.frames)))  // as the speedups it is compared with
        for (size_t t = 0; t < tile_ms.size(); ++t) tile_ms[t] += rr.tile_ms[t];
    }
    if (run_foveated) {
      const engine::RayCounts before = eng.counts();
      foveation::FrameRequest request;
      request.view = view;
      request.gaze_px = o.gaze_px_per_frame.empty()
                            ? gaze
                            : o.gaze_px_per_frame[std::min<std::size_t>(std::size_t(frame), o.gaze_px_per_frame.size() - 1)];
      request.frame_index = o.first_frame + static_cast<uint64_t>(frame);
      const foveation::FrameResult fr = foveated->render(request, eng.fn(), eng.user(), executor);
      if (!fr.ok()) {
        err << "fovea render: " << fr.message;
        if (eng.gpu && !eng.gpu->last_error().empty()) err << " (" << eng.gpu->last_error() << ")";
        err << "\n";
        return 1;
      }
      // The fixed part: reconstruction and the temporal history.
      fov_times.add(fr.select_ms + fr.trace_ms, fr.reconstruct_ms + fr.temporal_ms, fr.select_ms);
      if (frame == 0) {
        fov_rays = eng.counts() - before;
        fov_points = fr.points;
      }
    }
  }
  report["frames"] = o.frames;
  if (run_foveated) report["first_frame"] = o.first_frame;
  if (run_full)
    report["full"] = {{"rays", rays_json(full_rays)}, {"lanes_per_packet", packets_json(full_rays, eng)},
                      {"trace_ms", full_times.median_trace_ms()}, {"reconstruct_ms", 0.0},
                      {"total_ms", full_times.median_total_ms()}, {"frames_total_ms", full_times.total_ms},
                      {"white_clipped_fraction", foveation::white_clipped_fraction(full, *display)}};
  if (run_foveated) {
    report["points"] = fov_points;
    report["foveated"] = {{"rays", rays_json(fov_rays)},
                          {"lanes_per_packet", packets_json(fov_rays, eng)},
                          {"interpolation", o.interpolation},
                          {"k", reconstruction_k(o)},
                          {"density_scale", o.density_scale},
                          {"taa", o.taa},
                          {"pattern", foveation::fovea_pattern_name(fov_display_pattern)},
                          {"precompute_ms", precompute_ms},
                          {"trace_ms", fov_times.median_trace_ms()},
                          {"samples_ms", fov_times.median_samples_ms()},
                          {"reconstruct_ms", fov_times.median_reconstruct_ms()},
                          {"total_ms", fov_times.median_total_ms()},
                          {"frames_total_ms", fov_times.total_ms},
                          {"white_clipped_fraction", foveation::white_clipped_fraction(foveated->image(), *display)}};
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
      if (std::string e; !read_pfm(o.reference_file, &reference, &e)) {
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
      ro.baseline_spp = std::max(16, o.rays_per_point);  // far below this render and the price list's best full render
      ro.seed = o.seed;
      ro.pixel_filter = o.pixel_filter;
      ro.cache_dir = !o.reference_cache.empty() ? o.reference_cache
                     : !o.cache_dir.empty()      ? (std::filesystem::path(o.cache_dir) / "reference").string()
                                                 : std::string();
      std::string bad;
      std::optional<Reference> ref = converged_reference(
          eng.fn(), eng.user(), eng.scene_hash(), view, gaze, ro, executor,
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
    const foveation::ImageRgb reference_display = foveation::display_encode(reference, display->exposure);
    Json against = {{"reference", ref_json}};
    if (run_full)
      against["full"] = comparison_json(foveation::compare_images(reference_display, foveation::display_encode(full, display->exposure), ecc_map()));
    if (run_foveated)
      against["foveated"] = comparison_json(
          foveation::compare_images(reference_display, foveation::display_encode(foveated->image(), display->exposure), ecc_map()));
    report["errors_against_reference"] = against;
  }
  const double full_total = run_full ? full_times.median_total_ms() : 0.0;
  const double fov_total = run_foveated ? fov_times.median_total_ms() : 0.0;
  if (o.mode == "both") {
    report["speedup"] = median_pair_ratio(full_times.total_ms, fov_times.total_ms);
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
    // The speedup in its two parts: the sparse trace (selection + rays + trace),
    // which scales with the scene's cost, and the fixed per-frame cost of
    // reconstruction and history, which does not. Foveation pays while the full
    // frame costs more than fixed * s / (s - 1), s the trace's own speedup.
    const double fixed = fov_times.median_reconstruct_ms();
    const double trace_speedup = median_pair_ratio(full_times.total_ms, fov_times.trace_ms);
    report["speedup_parts"] = {
        {"trace_speedup", trace_speedup},
        {"trace_of_content_speedup", content_bound > 0.0 ? trace_speedup / content_bound : 0.0},
        {"fixed_ms", fixed},
        {"fixed_share_of_foveated", fov_total > 0.0 ? fixed / fov_total : 0.0},
        {"breakeven_full_ms", trace_speedup > 1.0 ? Json(fixed * trace_speedup / (trace_speedup - 1.0)) : Json(nullptr)}};
    // Agreement of the two images (both carry their own noise), not accuracy: see errors_against_reference.
    const foveation::ImageComparison cmp = foveation::compare_images(
        foveation::display_encode(full, display->exposure), foveation::display_encode(foveated->image(), display->exposure), ecc_map());
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
      if (std::string e; !toolkit::write_png(path, *img, *display, &e)) {
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
        << report["effects"].get<std::string>() << "), " << view.width_px << "x" << view.height_px << ", rays per point "
        << o.rays_per_point << "\n";
    out << "engine " << o.engine;
    if (eng.gpu) out << " (" << eng.gpu->device_name() << ", " << eng.gpu->backend_name() << "; each batch a device round trip, times include transfers)";
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
    out << "display: exposure " << display->exposure << " (" << report["display"]["exposure_from"].get<std::string>()
        << "), tone map " << foveation::tone_map_name(display->tone_map) << "\n";
  }
  return 0;
}

}  // namespace foveart::tools

void register_render(CLI::App& app) {
  auto opts = std::make_shared<foveart::tools::RenderOptions>();
  auto gaze = std::make_shared<std::string>();
  auto pose = std::make_shared<std::string>();
  CLI::App* cmd = app.add_subcommand(
      "render", "Render a glTF scene with the sample engine, CPU or GPU (full, foveated or both)");
  const std::function<void()> parse_common = foveart::tools::add_render_options(cmd, opts);
  foveart::tools::add_temporal_option(cmd, opts);
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
  cmd->add_option("--reference", opts->reference_file, "Errors against this linear-RGB PFM of the view");
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
        opts->gaze_px_per_frame.push_back(foveart::tools::parse_gaze_option("--gaze", item));
      opts->gaze_px = opts->gaze_px_per_frame.back();
    } else if (!gaze->empty()) {
      opts->gaze_px = foveart::tools::parse_gaze_option("--gaze", *gaze);
    }
    if (!pose->empty()) foveart::tools::parse_pose_option("--pose", *pose, opts.get());
    const int code = foveart::tools::run_render(*opts, std::cout, std::cerr);
    if (code != 0) throw CLI::RuntimeError(code);
  });
}
