// fovea reconstruct --image IN.png --preset fove --gaze X,Y --interpolation M --k K
//                   --density-scale S --rays-per-point N --out OUT.png [--json] [--frames F --jitter]
// The thesis's user-study pipeline on an image, through the one foveated frame
// (foveation::FoveatedView) whose "engine" samples the image: spp bilinear
// samples in each visible point's disc, every pixel reconstructed with the k-tap
// gather, the image history, and timings and error per ring.
#include <CLI/CLI.hpp>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>

#include <nlohmann/json.hpp>

#include "foveation/cache_dir.hpp"
#include "foveation/display_model.hpp"
#include "foveation/elapsed.hpp"
#include "foveation/executor.hpp"
#include "foveation/foveated_view.hpp"
#include <metrics/image_metrics.hpp>
#include "interp_commands.hpp"
#include <metrics/comparison_json.hpp>
#include "toolkit/image_io.hpp"
#include "toolkit/outputs.hpp"

namespace foveart::fovea {

namespace fv = foveart::foveation;

namespace {

using foveation::ms_since;

// Bilinear sample of a [0, 1] RGB image at a screen position (pixel centres at
// +0.5, clamped to the edge).
void bilinear(const fv::ImageRgb& im, float x, float y, float* rgb) {
  const float fx = std::clamp(x - 0.5f, 0.0f, float(im.width_px - 1));
  const float fy = std::clamp(y - 0.5f, 0.0f, float(im.height_px - 1));
  const int x0 = int(fx), y0 = int(fy);
  const int x1 = std::min(x0 + 1, im.width_px - 1), y1 = std::min(y0 + 1, im.height_px - 1);
  const float tx = fx - float(x0), ty = fy - float(y0);
  const float* a = im.at(x0, y0);
  const float* b = im.at(x1, y0);
  const float* c = im.at(x0, y1);
  const float* d = im.at(x1, y1);
  for (int i = 0; i < 3; ++i) {
    rgb[i] = (a[i] * (1 - tx) + b[i] * tx) * (1 - ty) + (c[i] * (1 - tx) + d[i] * tx) * ty;
  }
}

// The "engine" of an image: each ray's colour is the image at its sample position.
int32_t sample_image(void* user_data, const FoveartRayBatch* batch) {
  const auto* image = static_cast<const fv::ImageRgb*>(user_data);
  for (uint32_t i = 0; i < batch->ray_count; ++i) {
    bilinear(*image, batch->sample_px[2 * i], batch->sample_px[2 * i + 1], batch->out_rgb + 3 * i);
  }
  return FOVEART_RESULT_SUCCESS;
}

// --cache-dir, else $FOVEART_CACHE_DIR, else the one default rule the layer uses
// (foveation::default_cache_dir); *why says why there is none.
std::optional<std::filesystem::path> cache_dir_of(const ReconstructArgs& a, std::string* why) {
  if (a.no_cache) return std::nullopt;
  if (!a.cache_dir.empty()) return std::filesystem::path(a.cache_dir);
  if (const char* e = std::getenv("FOVEART_CACHE_DIR"); e && *e) return std::filesystem::path(e);
  return fv::default_cache_dir(why);
}

}  // namespace

namespace {

constexpr const char* kReconstructWho = "fovea reconstruct: ";

// The checks before any work: the options and the output file. False and *error.
[[nodiscard]] bool check_args(const ReconstructArgs& a, std::string* error) {
  const auto fail = [&](std::string m) {
    *error = std::move(m);
    return false;
  };
  if (!fv::parse_method(a.interpolation))
    return fail("unknown --interpolation '" + a.interpolation + "' (nearest, msm, rbf, rbf-gauss)");
  if (a.k < 1 || a.k > fv::kMaxNeighbors) return fail("--k must be in 1..20");
  if (a.rays_per_point < 1 || a.rays_per_point > 4096) return fail("--rays-per-point must be in 1..4096");
  if (!(a.density_scale > 0.0) || !std::isfinite(a.density_scale))
    return fail("--density-scale must be a positive number");
  if (a.frames < 1 || a.frames > 10000) return fail("--frames must be in 1..10000");
  if (!fv::parse_rbf_clamp(a.rbf_clamp)) return fail("unknown --rbf-clamp '" + a.rbf_clamp + "' (off, taps, block)");
  if (!fv::display_preset(a.preset)) {
    std::string names;
    for (const auto& n : fv::display_preset_names()) names += (names.empty() ? "" : ", ") + n;
    return fail("unknown --preset '" + a.preset + "' (" + names + ")");
  }
  if (!a.gaze.empty()) {
    float gx = 0, gy = 0;
    char extra = 0;
    if (std::sscanf(a.gaze.c_str(), "%f,%f%c", &gx, &gy, &extra) != 2 || !std::isfinite(gx) || !std::isfinite(gy))
      return fail("--gaze '" + a.gaze + "' is not X,Y in pixels");
  }
  if (!a.out.empty() && !toolkit::check_writable_file(a.out, error)) return fail("--out: " + *error);
  return true;
}

// The image's own display: the preset's field of view at the image's size.
std::optional<fv::DisplayModel> image_display(const ReconstructArgs& a, int w, int h, std::string* error) {
  std::optional<fv::DisplayModel> display = fv::display_preset(a.preset);
  display->view_distance_px *= double(w) / double(display->width_px);
  display->width_px = w;
  display->height_px = h;
  display->scale = a.density_scale;
  if (auto e = display->validate(); !e.empty()) {
    *error = "display: " + e;
    return std::nullopt;
  }
  return display;
}

// Point set, neighbour table and weights: cached, not part of the frame time.
std::shared_ptr<const fv::ViewTables> load_tables(const ReconstructArgs& a, const fv::DisplayModel& display,
                                                  fv::Executor& executor, std::ostream& err) {
  auto log = [&](const std::string& m) {
    if (!a.json) err << kReconstructWho << m << "\n";
  };
  std::string no_cache_why;
  const auto cache = cache_dir_of(a, &no_cache_why);
  if (!cache && !no_cache_why.empty()) log("no table cache: " + no_cache_why);
  fv::InterpOptions io;
  io.method = *fv::parse_method(a.interpolation);
  io.k = a.k;
  io.shape = a.shape;
  io.constant_term = !a.no_constant;
  std::optional<fv::WeightPrecision> precision;
  if (a.weights == "f16") precision = fv::WeightPrecision::f16;
  if (a.weights == "f32") precision = fv::WeightPrecision::f32;
  return fv::load_view_tables(cache, fv::PointSetKey{display, a.seed, a.k}, io, executor, precision, {}, log);
}

// The frames' times summed, their flicker (with and without the history) and the last frame.
struct Run {
  double sample_ms = 0, interpolate_ms = 0, temporal_ms = 0, total_ms = 0;
  double flicker = 0, flicker_raw = 0;
  fv::FrameResult frame;
};

// --frames frames of the image through the foveated view; false and *error when a frame fails.
[[nodiscard]] bool run_frames(const ReconstructArgs& a, fv::FoveatedView& view, const fv::FrameRequest& first,
                              fv::ImageRgb& image, fv::Executor& executor, Run* r, std::string* error) {
  fv::FrameRequest request = first;
  fv::ImageRgb prev_out, prev_raw;
  for (int t = 0; t < a.frames; ++t) {
    request.frame_index = std::uint64_t(t);
    r->frame = view.render(request, &sample_image, &image, executor);
    if (!r->frame.ok()) {
      *error = r->frame.message;
      return false;
    }
    r->sample_ms += r->frame.select_ms + r->frame.trace_ms;
    r->interpolate_ms += r->frame.reconstruct_ms;
    r->temporal_ms += r->frame.temporal_ms;
    r->total_ms += r->frame.select_ms + r->frame.trace_ms + r->frame.reconstruct_ms + r->frame.temporal_ms;
    if (t > 0) {
      r->flicker += metrics::mean_abs_difference(view.image(), prev_out);
      r->flicker_raw += metrics::mean_abs_difference(view.reconstructed(), prev_raw);
    }
    prev_out = view.image();
    prev_raw = view.reconstructed();
  }
  return true;
}

nlohmann::json report_json(const ReconstructArgs& a, const fv::ViewTables& tables, const fv::FrameRequest& request,
                           const fv::ImageRgb& image, const fv::ImageRgb& output, const Run& r, double setup_ms) {
  const double nf = double(a.frames);
  const fv::GatherStats gstats = r.frame.gather;
  // Rings by the angle between a pixel's ray and the gaze ray in the image's own view.
  const glm::vec2 gaze = fv::map_gaze(image.width_px, image.height_px, request.gaze_px).gaze_px;
  const metrics::ImageComparison cmp =
      metrics::compare_images(image, output, metrics::eccentricity_map(request.view, gaze));
  nlohmann::json j;
  j["image"] = a.image;
  j["preset"] = a.preset;
  j["interpolation"] = std::string(fv::method_name(*fv::parse_method(a.interpolation)));
  j["k"] = a.k;
  j["density_scale"] = a.density_scale;
  j["rays_per_point"] = a.rays_per_point;
  j["gaze"] = {gaze.x, gaze.y};
  j["points"] = r.frame.points;
  j["points_total"] = tables.points.size();
  j["pixels"] = std::size_t(image.width_px) * std::size_t(image.height_px);
  j["frames"] = a.frames;
  j["sample_ms"] = r.sample_ms / nf;
  j["interpolate_ms"] = r.interpolate_ms / nf;
  j["temporal_ms"] = r.temporal_ms / nf;
  j["total_ms"] = r.total_ms / nf;
  j["setup_ms"] = setup_ms;
  j["table_from_cache"] = tables.from_cache;
  j["table_weight_bytes"] = tables.interpolation.bytes();
  j["table_index_bytes"] = tables.neighbors.bytes();
  j["weights"] = tables.interpolation.precision == fv::WeightPrecision::f16 ? "f16" : "f32";
  j["rbf_clamp"] = fv::rbf_clamp_name(*fv::parse_rbf_clamp(a.rbf_clamp));
  j["rbf_fallback_pixels"] = tables.interpolation.stats.fallback_msm;
  j["invalid_tap_pixels"] = gstats.renormalized + gstats.nearest_valid + gstats.fallback;
  j["psnr"] = metrics::number_or_null_json(metrics::psnr(image, output));
  j["ssim"] = metrics::ssim(image, output);
  if (a.frames > 1) {
    j["flicker"] = r.flicker / (nf - 1.0);
    j["flicker_no_history"] = r.flicker_raw / (nf - 1.0);
  }
  j["csf_rmse"] = metrics::number_or_null_json(cmp.csf_rmse);
  j["rings"] = metrics::comparison_json(cmp)["rings"];
  return j;
}

// The whole pipeline after the checks; returns the exit code.
int reconstruct(const ReconstructArgs& a, std::ostream& out, std::ostream& err) {
  const auto fail = [&](const std::string& msg) {
    err << kReconstructWho << msg << "\n";
    return 1;
  };
  fv::ImageRgb image;  // the input, as display values in [0, 1]
  std::string error;
  if (!toolkit::read_image(a.image, toolkit::PngValues::display, &image, &error)) return fail(error);
  const int w = image.width_px, h = image.height_px;
  const std::optional<fv::DisplayModel> display = image_display(a, w, h, &error);
  if (!display) return fail(error);
  fv::Executor executor(static_cast<unsigned>(std::max(0, a.threads)));
  const auto t_setup = std::chrono::steady_clock::now();
  const auto tables = load_tables(a, *display, executor, err);
  const double setup_ms = ms_since(t_setup);
  fv::ViewSettings settings;
  settings.rays_per_point = a.rays_per_point;
  settings.sample_seed = a.seed;
  settings.new_jitter_each_frame = a.jitter;
  settings.temporal = fv::TemporalMode::image;
  settings.rbf_clamp = *fv::parse_rbf_clamp(a.rbf_clamp);
  fv::FoveatedView view(tables, settings);
  fv::FrameRequest request;  // the image's own view: a pinhole D pixels from the eye
  const float half_x = float(std::atan(0.5 * w / display->view_distance_px));
  const float half_y = float(std::atan(0.5 * h / display->view_distance_px));
  request.view =
      fv::make_eye_view(0, std::uint32_t(w), std::uint32_t(h), fv::EyePose{}, -half_x, half_x, half_y, -half_y);
  glm::vec2 gaze{float(w) / 2.0f, float(h) / 2.0f};
  if (!a.gaze.empty()) std::sscanf(a.gaze.c_str(), "%f,%f", &gaze.x, &gaze.y);  // checked by check_args
  request.gaze_px = gaze;
  Run r;
  if (!run_frames(a, view, request, image, executor, &r, &error)) return fail(error);
  if (!a.out.empty() && !toolkit::write_png(a.out, view.image(), toolkit::PngValues::display, &error))
    return fail(error);
  const nlohmann::json j = report_json(a, *tables, request, image, view.image(), r, setup_ms);
  if (a.json) {
    out << j.dump(2) << "\n";
  } else {
    const double nf = double(a.frames);
    out << "points " << r.frame.points << ", " << w << "x" << h << " px, " << j["interpolation"].get<std::string>()
        << " k=" << a.k << ": sample " << r.sample_ms / nf << " ms, interpolate " << r.interpolate_ms / nf
        << " ms, temporal " << r.temporal_ms / nf << " ms, total " << r.total_ms / nf << " ms; PSNR "
        << metrics::psnr(image, view.image()) << " dB, SSIM " << j["ssim"].get<double>() << "\n";
  }
  return 0;
}

}  // namespace

int run_reconstruct(const ReconstructArgs& a, std::ostream& out, std::ostream& err) {
  if (std::string bad; !check_args(a, &bad)) {
    err << kReconstructWho << bad << "\n";
    return 2;
  }
  try {
    return reconstruct(a, out, err);
  } catch (const std::exception& e) {  // the tables' cache or build: what failed, named by the library
    err << kReconstructWho << e.what() << "\n";
    return 1;
  }
}

void register_reconstruct(CLI::App& app) {
  auto a = std::make_shared<ReconstructArgs>();
  auto* sub = app.add_subcommand("reconstruct", "Foveate an image: sample it at the visible points and reconstruct");
  sub->add_option("--image", a->image, "input PNG (or any format stb_image reads)")->required();
  sub->add_option("--preset", a->preset, "display preset (fove, vive, thesis)")->capture_default_str();
  sub->add_option("--gaze", a->gaze, "gaze X,Y in pixels (default: image centre)");
  sub->add_option("--interpolation", a->interpolation, "nearest, msm, rbf or rbf-gauss")->capture_default_str();
  sub->add_option("--k", a->k, "neighbours per pixel, 1..20")->capture_default_str();
  sub->add_option("--density-scale", a->density_scale, "density scale of the point set")->capture_default_str();
  sub->add_option("--rays-per-point", a->rays_per_point, "samples per point (bilinear, in the point's disc)")
      ->capture_default_str();
  sub->add_option("--out", a->out, "output PNG");
  sub->add_flag("--json", a->json, "print a JSON report");
  sub->add_option("--frames", a->frames, "frames to run through the image history (static gaze)")
      ->capture_default_str();
  sub->add_flag("--jitter", a->jitter, "new sample positions every frame (to measure flicker)");
  sub->add_option("--seed", a->seed, "point set and sample seed")->capture_default_str();
  sub->add_option("--cache-dir", a->cache_dir, "cache directory (default $FOVEART_CACHE_DIR, $XDG_CACHE_HOME/foveart)");
  sub->add_flag("--no-cache", a->no_cache, "build everything, store nothing");
  sub->add_option("--threads", a->threads, "threads (0 = all cores)")
      ->check(CLI::Range(0, int(fv::kMaxExecutorThreads)))
      ->capture_default_str();
  sub->add_option("--shape", a->shape, "RBF shape eps0 (0 = default)");
  sub->add_flag("--no-constant", a->no_constant, "RBF without the constant term (thesis form)");
  sub->add_option("--weights", a->weights, "weight storage f16 or f32 (default f16)")
      ->check(CLI::IsMember({"f16", "f32"}));
  sub->add_option("--rbf-clamp", a->rbf_clamp,
                  "RBF de-ringing: each pixel within its block's point colours (block), its own taps' (taps), "
                  "or none (off, the thesis)")
      ->check(CLI::IsMember({"off", "taps", "block"}))
      ->capture_default_str();
  sub->callback([a] {
    const int rc = run_reconstruct(*a, std::cout, std::cerr);  // never throws: problems are its exit code
    if (rc != 0) throw CLI::RuntimeError(rc);
  });
}

}  // namespace foveart::fovea
