// `fovea-eval accuracy` (cmd_accuracy.hpp): render one still view, measure it
// per ring against a converged reference or a reference image.
#include <eval/cmd_accuracy.hpp>

#include <eval/pfm.hpp>
#include <eval/reference.hpp>
#include <eval/temporal_variants.hpp>

#include <render_view/render_cli.hpp>

#include <metrics/comparison_json.hpp>
#include <metrics/image_metrics.hpp>

#include <engine/gltf_loader.hpp>
#include <engine/render.hpp>
#include <engine/tracer.hpp>

#include <foveation/foveated_view.hpp>

#include <toolkit/image_io.hpp>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <iostream>
#include <memory>
#include <optional>
#include <vector>

namespace foveart::eval {
namespace {

using Json = nlohmann::ordered_json;

constexpr const char* kAccuracyWho = "fovea-eval accuracy: ";

std::string options_problem(const AccuracyOptions& o, TemporalVariant* variant) {
  std::string bad;
  if (!render_view::check_render_options(o.render, &bad)) return bad;
  if (!check_reference_choice(o.reference, &bad)) return bad;
  if (o.reference.spp.empty() && o.reference.file.empty())
    return "give the reference: --reference-spp auto|N (a converged full render) or --reference FILE.pfm";
  std::vector<TemporalVariant> variants;
  if (!parse_temporal_variants(o.temporal, &variants, &bad)) return bad;
  if (variants.size() != 1) return "--temporal: one still view has one temporal variant";
  *variant = variants.front();
  if (o.render.mode == "full" && *variant != TemporalVariant::off) return "--temporal needs --mode foveated or both";
  return "";
}

// The scene, its CPU tracer and what the view needs to be rendered and shown.
struct Still {
  std::unique_ptr<engine::Tracer> tracer;
  FoveartEyeView view{};
  glm::vec2 gaze{};
  foveation::DisplayTransform display;
};

// Loads the scene and sets up the view; false with *error on failure.
[[nodiscard]] bool set_up(const AccuracyOptions& o, foveation::Executor& executor, std::ostream& err, Still* s,
                          std::string* error) {
  engine::LoadResult loaded = engine::load_scene(o.render.scene);
  if (!loaded.ok()) {
    *error = loaded.error;
    return false;
  }
  for (const std::string& w : loaded.scene->warnings) err << kAccuracyWho << "warning: " << w << "\n";
  s->tracer = engine::Tracer::create(std::move(*loaded.scene), render_view::render_tracer_options(o.render), error);
  if (!s->tracer) return false;
  s->view = render_view::eye_view(o.render, s->tracer->scene());
  s->gaze = o.render.gaze_px.value_or(
      glm::vec2(0.5f * static_cast<float>(s->view.width_px), 0.5f * static_cast<float>(s->view.height_px)));
  const std::optional<foveation::DisplayTransform> display =
      render_view::render_display(o.render, *s->tracer, s->view, executor, error);
  if (!display) return false;
  s->display = *display;
  return true;
}

// The images measured: the full render (one frame: every frame traces the same rays) and the
// foveated view's last frame after --frames frames with its temporal history.
struct Images {
  std::optional<foveation::ImageRgb> full;
  std::optional<foveation::ImageRgb> foveated;
};

[[nodiscard]] bool render_images(const AccuracyOptions& o, TemporalVariant variant, const Still& s,
                                 foveation::Executor& executor, std::ostream& err, Images* images, std::string* error) {
  const render_view::RenderOptions& r = o.render;
  if (r.mode != "foveated") {
    engine::RenderSettings rs;
    rs.spp = r.rays_per_point;
    rs.seed = r.seed;
    rs.pixel_filter = r.pixel_filter;
    images->full.emplace();
    const engine::RenderResult rr = engine::render_full(&foveart_engine_trace_rays, s.tracer.get(), s.view, rs,
                                                        &*images->full, executor);
    if (rr.status != FOVEART_RESULT_SUCCESS) {
      *error = "full render: engine callback failed with status " + std::to_string(rr.status);
      return false;
    }
  }
  if (r.mode == "full") return true;
  std::optional<std::filesystem::path> cache;
  if (!r.cache_dir.empty()) cache = std::filesystem::path(r.cache_dir);
  auto tables = render_view::load_foveated_tables(
      r, s.view, cache, executor, [&](const std::string& m) { err << kAccuracyWho << m << "\n"; }, error);
  if (!tables) return false;
  const std::unique_ptr<foveation::FoveatedView> view =
      make_variant_view(variant, std::move(tables), variant_settings(r, o.mean_while_young, s.display.exposure));
  for (int frame = 0; frame < r.frames; ++frame) {
    foveation::FrameRequest request;
    request.view = s.view;
    request.gaze_px = s.gaze;
    request.frame_index = r.first_frame + static_cast<std::uint64_t>(frame);
    const foveation::FrameResult fr = view->render(request, &foveart_engine_trace_rays, s.tracer.get(), executor);
    if (!fr.ok()) {
      *error = "foveated frame " + std::to_string(frame) + ": " + fr.message;
      return false;
    }
  }
  images->foveated = view->image();
  return true;
}

// The reference image (linear RGB) and what it is, as JSON; false with *error.
[[nodiscard]] bool reference_of(const AccuracyOptions& o, const Still& s, const metrics::EccentricityMap& map,
                  foveation::Executor& executor, std::ostream& err, foveation::ImageRgb* image, Json* about,
                  std::string* error) {
  if (!o.reference.file.empty()) {
    if (!read_pfm(o.reference.file, image, error)) {
      *error = "--reference: " + *error;
      return false;
    }
    if (image->width_px != int(s.view.width_px) || image->height_px != int(s.view.height_px)) {
      *error = "--reference: " + o.reference.file + " is " + std::to_string(image->width_px) + "x" +
               std::to_string(image->height_px) + ", the view is " + std::to_string(s.view.width_px) + "x" +
               std::to_string(s.view.height_px);
      return false;
    }
    *about = {{"source", "file"}, {"file", o.reference.file}};
    return true;
  }
  ReferenceOptions ro;
  if (o.reference.spp != "auto") ro.spp = std::stoi(o.reference.spp);
  ro.baseline_spp = std::max(16, o.render.rays_per_point);  // far below this render and the price list's best
  ro.seed = o.render.seed;
  ro.pixel_filter = o.render.pixel_filter;
  ro.cache_dir = reference_cache_dir(o.reference, o.render.cache_dir);
  std::optional<Reference> ref =
      converged_reference(&foveart_engine_trace_rays, s.tracer.get(), rendered_scene_hash(*s.tracer), s.view, s.gaze,
                          ro, executor, [&](const std::string& m) { err << kAccuracyWho << m << "\n"; }, error);
  if (!ref) return false;
  Json residual = Json::array();
  for (double mse : ref->residual_mse(map))
    residual.push_back(metrics::number_or_null_json(metrics::psnr_of_mse(mse)));
  *about = {{"source", "converged full render"}, {"spp", ref->spp}, {"spp_tried", ref->tried_spp},
            {"converged", ref->converged}, {"db_per_doubling", ref->db_per_doubling},
            {"from_cache", ref->from_cache}, {"cache_file", ref->cache_file}, {"render_ms", ref->render_ms},
            {"residual_psnr", residual}};
  *image = std::move(ref->image);
  return true;
}

// --out PREFIX: the images measured as PREFIX_full.png and PREFIX_foveated.png; false with *error.
[[nodiscard]] bool write_images(const AccuracyOptions& o, const Still& s, const Images& images, Json* files,
                                std::string* error) {
  *files = Json::array();
  for (const auto& [image, suffix] :
       {std::pair{&images.full, "_full.png"}, std::pair{&images.foveated, "_foveated.png"}}) {
    if (!image->has_value()) continue;
    const std::string path = o.render.out_prefix + suffix;
    if (!toolkit::write_png(path, **image, s.display, error)) return false;
    files->push_back(path);
  }
  return true;
}

Json report_head(const AccuracyOptions& o, const Still& s) {
  const render_view::RenderOptions& r = o.render;
  Json j;
  j["scene"] = s.tracer->scene().source;
  j["effects"] = engine::to_string(s.tracer->effects());
  j["eye"] = r.eye;
  j["width"] = s.view.width_px;
  j["height"] = s.view.height_px;
  j["gaze"] = {s.gaze.x, s.gaze.y};
  j["rays_per_point"] = r.rays_per_point;
  j["pixel_filter"] = foveation::pixel_filter_name(r.pixel_filter);
  if (r.mode != "full") {
    j["foveated_settings"] = {{"interpolation", r.interpolation}, {"k", render_view::reconstruction_k(r)},
                              {"density_scale", r.density_scale}, {"temporal", o.temporal},
                              {"temporal_mean_while_young", o.mean_while_young}, {"frames", r.frames},
                              {"first_frame", r.first_frame}};
  }
  j["display"] = {{"exposure", s.display.exposure}, {"tone_map", foveation::tone_map_name(s.display.tone_map)}};
  return j;
}

void print_text(const Json& report, std::ostream& out) {
  const Json& against = report["errors_against_reference"];
  const Json& ref = against["reference"];
  out << "scene " << report["scene"].get<std::string>() << ", " << report["width"] << "x" << report["height"]
      << ", rays per point " << report["rays_per_point"] << "; reference: " << ref["source"].get<std::string>();
  if (ref.contains("spp"))
    out << ", " << ref["spp"] << " rays per pixel" << (ref["converged"] == true ? "" : " (not converged)");
  out << "\n";
  for (const char* image : {"full", "foveated"}) {
    if (!against.contains(image)) continue;
    const Json& c = against[image];
    out << image << ": PSNR " << c["psnr"].dump() << " dB, SSIM " << c["ssim"].dump() << "; PSNR per ring";
    for (const Json& ring : c["rings"]) out << " " << ring["psnr"].dump();
    out << "\n";
  }
}

}  // namespace

int run_accuracy(const AccuracyOptions& o, std::ostream& out, std::ostream& err) {
  TemporalVariant variant{};
  if (const std::string bad = options_problem(o, &variant); !bad.empty()) {
    err << kAccuracyWho << bad << "\n";
    return 2;
  }
  foveation::Executor executor(static_cast<unsigned>(o.render.threads));
  Still s;
  Images images;
  std::string error;
  if (!set_up(o, executor, err, &s, &error) || !render_images(o, variant, s, executor, err, &images, &error)) {
    err << kAccuracyWho << error << "\n";
    return 1;
  }
  const metrics::EccentricityMap map = metrics::eccentricity_map(s.view, s.gaze);
  foveation::ImageRgb reference;
  Json about;
  if (!reference_of(o, s, map, executor, err, &reference, &about, &error)) {
    err << kAccuracyWho << error << "\n";
    return 1;
  }
  Json report = report_head(o, s);
  const foveation::ImageRgb reference_display = metrics::display_encode(reference, s.display.exposure);
  Json against = {{"reference", about}};
  for (const auto& [image, name] : {std::pair{&images.full, "full"}, std::pair{&images.foveated, "foveated"}}) {
    if (!image->has_value()) continue;
    const foveation::ImageRgb shown = metrics::display_encode(**image, s.display.exposure);
    against[name] = metrics::comparison_json(metrics::compare_images(reference_display, shown, map));
  }
  report["errors_against_reference"] = against;
  if (!o.render.out_prefix.empty()) {
    Json files;
    if (!write_images(o, s, images, &files, &error)) {
      err << kAccuracyWho << error << "\n";
      return 1;
    }
    report["images"] = files;
  }
  if (o.render.json)
    out << report.dump(2) << "\n";
  else
    print_text(report, out);
  return 0;
}

void register_accuracy(CLI::App& app) {
  auto o = std::make_shared<AccuracyOptions>();
  auto gaze = std::make_shared<std::string>();
  auto pose = std::make_shared<std::string>();
  CLI::App* cmd = app.add_subcommand(
      "accuracy",
      "Render one still view (full, foveated or both) and measure it per ring against a converged reference");
  const std::shared_ptr<render_view::RenderOptions> render(o, &o->render);
  const std::function<void()> parse_common = render_view::add_render_options(cmd, render);
  add_temporal_lab_options(cmd, &o->temporal, &o->mean_while_young, /*list=*/false);
  add_reference_options(cmd, &o->reference, /*with_file=*/true);
  cmd->add_option("--gaze", *gaze, "Gaze X,Y in pixels of the eye image (default: centre)");
  cmd->add_option("--first-frame", o->render.first_frame,
                  "Index of the first foveated frame; with a history each frame's jitter seed is --seed plus its index")
      ->capture_default_str();
  cmd->add_option("--pose", *pose,
                  "Where the viewer stands, X,Y,Z (the head; the eye 32 mm aside), or an exact eye pose "
                  "px,py,pz,qx,qy,qz,qw (metres, unit quaternion; scene space)");
  cmd->callback([o, gaze, pose, parse_common] {
    parse_common();
    if (!gaze->empty()) o->render.gaze_px = render_view::parse_gaze_option("--gaze", *gaze);
    if (!pose->empty()) render_view::parse_pose_option("--pose", *pose, &o->render);
    const int code = run_accuracy(*o, std::cout, std::cerr);
    if (code != 0) throw CLI::RuntimeError(code);
  });
}

}  // namespace foveart::eval
