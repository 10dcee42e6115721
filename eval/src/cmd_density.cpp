// `fovea-eval density` (cmd_density.hpp).
#include <eval/cmd_density.hpp>

#include <eval/density_detection.hpp>
#include <eval/detection_png.hpp>
#include <eval/reference.hpp>
#include <render_view/render_cli.hpp>

#include <engine/gltf_loader.hpp>
#include <engine/render.hpp>
#include <foveation/content_density.hpp>
#include <foveation/display_model.hpp>
#include <metrics/image_metrics.hpp>
#include <toolkit/image_io.hpp>
#include <toolkit/outputs.hpp>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>

namespace foveart::eval {
namespace {

constexpr const char* kDensityWho = "fovea-eval density: ";
using Json = nlohmann::ordered_json;

// What is wrong with the options ("" when nothing); a crop becomes the view's size and field of view.
std::string density_problem(DensityOptions& o) {
  if (o.reference.spp.empty() || !o.reference.file.empty()) return "--reference-spp N is required";
  std::string bad;
  if (!check_reference_choice(o.reference, &bad)) return bad;
  for (const double s : o.scales)
    if (!(s > 0.0 && s <= 100.0)) return "--scales: each density scale must be in (0, 100]";
  for (const double c : o.contrasts)
    if (!(c > 0.0 && c <= 1.0)) return "--contrasts: each content contrast must be in (0, 1]";
  for (const double c : o.ray_contrasts)
    if (!(c > 0.0 && c <= 1.0)) return "--ray-contrasts: each contrast must be in (0, 1]";
  for (const double c : o.both_contrasts)
    if (!(c > 0.0 && c <= 1.0)) return "--both-contrasts: each contrast must be in (0, 1]";
  for (const double d : o.rays_doublings)
    if (!foveation::valid_rays_doubling_ecc_deg(d)) return "--rays-doublings: each must be in [0, 90] degrees (0: off)";
  if (o.rays_doublings.empty()) o.rays_doublings = {render_view::content_rays_doubling_of(o.render)};
  if (!(o.white_cd_m2 > 0.0 && std::isfinite(o.white_cd_m2))) return "--white-cd-m2 must be positive";
  if (o.crop_px) {
    std::optional<foveation::DisplayModel> crop = foveation::display_preset(o.render.preset);
    if (!crop) return "--crop needs a display preset, got '" + o.render.preset + "'";
    if (o.crop_px->x < 8 || o.crop_px->y < 8 || o.crop_px->x > crop->width_px || o.crop_px->y > crop->height_px)
      return "--crop must lie inside the preset's view";
    crop->width_px = o.crop_px->x;  // the preset's viewing distance, the crop's size
    crop->height_px = o.crop_px->y;
    o.render.size_px = *o.crop_px;
    o.render.fov.horizontal = crop->horizontal_fov_deg();
  }
  o.render.mode = "foveated";
  if (!o.render.out_prefix.empty() && !toolkit::check_writable_file(o.render.out_prefix + "_full.png", &bad))
    return "--out: " + bad;
  return render_view::check_render_options(o.render, &bad) ? "" : bad;
}

// The scene, the view, the gaze, the reference and the metric on the view's display.
struct DensityRun {
  std::unique_ptr<engine::Tracer> tracer;
  FoveartEyeView view{};
  glm::vec2 gaze{};
  foveation::ImageRgb reference;
  int reference_spp = 0;
  foveation::DisplayTransform display;  // the view's exposure and tone map, the images written through it
  PerceptualMetric metric;
};

[[nodiscard]] bool set_up_density(const DensityOptions& o, const render_view::RenderOptions& whole_view,
                                  foveation::Executor& executor, std::ostream& err, DensityRun* r, std::string* error) {
  engine::LoadResult loaded = engine::load_scene(o.render.scene);
  if (!loaded.ok()) return *error = loaded.error, false;
  r->tracer = engine::Tracer::create(std::move(*loaded.scene), render_view::render_tracer_options(o.render), error);
  if (!r->tracer) return false;
  r->view = render_view::eye_view(o.render, r->tracer->scene());
  r->gaze = o.render.gaze_px.value_or(glm::vec2(0.5f * float(r->view.width_px), 0.5f * float(r->view.height_px)));
  // A crop's display is the whole view's: "auto" exposure meters the preset's whole view, so
  // that the crop shows what the whole view shows there (metered alone, a crop of a bright
  // place comes out darker than the whole view shows it).
  const FoveartEyeView metered = o.crop_px ? render_view::eye_view(whole_view, r->tracer->scene()) : r->view;
  const auto display = render_view::render_display(o.render, *r->tracer, metered, executor, error);
  if (!display) return false;
  ReferenceOptions ro;
  if (o.reference.spp != "auto") ro.spp = std::stoi(o.reference.spp);  // checked by check_reference_choice
  ro.baseline_spp = o.render.rays_per_point;
  ro.seed = o.render.seed;
  ro.pixel_filter = o.render.pixel_filter;
  ro.cache_dir = reference_cache_dir(o.reference, o.render.cache_dir);
  const auto ref = converged_reference(&foveart_engine_trace_rays, r->tracer.get(), rendered_scene_hash(*r->tracer),
                                       r->view, r->gaze, ro, executor,
                                       [&](const std::string& m) { err << kDensityWho << m << "\n"; }, error);
  if (!ref) return false;
  r->reference = ref->image;
  r->reference_spp = ref->spp;
  PerceptualDisplay pd = view_display(metrics::eccentricity_map(r->view, r->gaze), o.render.eye == "left" ? Eye::kLeft : Eye::kRight);
  pd.white_luminance_cd_m2 = o.white_cd_m2;
  pd.transform = r->display = *display;
  return PerceptualMetric::create(pd, int(r->view.width_px), int(r->view.height_px), {}, r->metric, *error, &executor);
}

// Each ring's largest P; NaN where the ring has no pixels.
std::vector<double> ring_p_max(const PerceptualResult& p) {
  std::vector<double> v;
  for (const PerceptualRing& r : p.rings) v.push_back(r.pixels > 0 ? r.p_max : std::nan(""));
  return v;
}

Json rings_p_max(const PerceptualResult& p) {
  Json a = Json::array();
  for (const PerceptualRing& r : p.rings) a.push_back(r.pixels > 0 ? Json(r.p_max) : Json());
  return a;
}

// Each ring's threshold multiple (null where the ring has no pixels); nothing when not measured.
void add_ring_multiples(const PerceptualResult& p, const std::vector<double>& multiples, Json* row) {
  if (multiples.empty()) return;
  Json a = Json::array();
  for (std::size_t r = 0; r < p.rings.size() && r < multiples.size(); ++r)
    a.push_back(p.rings[r].pixels > 0 ? Json(multiples[r]) : Json());
  (*row)["rings_threshold_multiple"] = std::move(a);
}

Json row_json(const char* kind, const DensityDetection& d, const PerceptualResult& full) {
  Json row = {{"kind", kind},
              {"density_scale", d.density_scale},
              {"content_contrast", d.content_contrast},
              {"content_rays", d.content_rays},
              {"content_rays_doubling_deg", d.content_rays_doubling_deg},
              {"ray_fraction", d.ray_fraction},
              {"density_ms", d.density_ms},
              {"frame_ms", d.frame_ms},
              {"p_max", d.p.p_max},
              {"rings_p_max", rings_p_max(d.p)},
              {"unseen", unseen_in_every_ring(ring_p_max(d.p), ring_p_max(full))}};
  add_ring_multiples(d.p, d.ring_multiples, &row);
  return row;
}

// --out PREFIX: a measured image as PREFIX_<name>.png on the view's display and, with its
// measurement, P per pixel as PREFIX_<name>_p.png; the paths into *files. False with *error.
[[nodiscard]] bool write_measured(const std::string& prefix, const std::string& name, const foveation::ImageRgb& image,
                                  const foveation::DisplayTransform& display, const PerceptualResult* p, Json* files,
                                  std::string* error) {
  const std::string path = prefix + "_" + name + ".png";
  if (!toolkit::write_png(path, image, display, error)) return false;
  files->push_back(path);
  if (p == nullptr) return true;
  const std::string p_path = prefix + "_" + name + "_p.png";
  if (!write_detection_png(p_path, *p, error)) return false;
  files->push_back(p_path);
  return true;
}

// A row's name in the images' file names: its kind and the value it sweeps.
std::string row_image_name(const char* kind, double scale, double contrast, double rays_contrast,
                           double rays_doubling_deg) {
  char name[128];
  if (std::string(kind) == "eccentricity")
    std::snprintf(name, sizeof name, "%s_scale_%g", kind, scale);
  else if (rays_doubling_deg > 0.0)
    std::snprintf(name, sizeof name, "%s_contrast_%g_doubling_%g", kind, contrast > 0.0 ? contrast : rays_contrast,
                  rays_doubling_deg);
  else
    std::snprintf(name, sizeof name, "%s_contrast_%g", kind, contrast > 0.0 ? contrast : rays_contrast);
  return name;
}

// The baseline: the full render at the rows' rays per pixel against the reference, and its ms
// (with --out, the reference's and its images too).
[[nodiscard]] bool baseline_json(const DensityOptions& o, DensityRun& r, foveation::Executor& executor,
                                 PerceptualResult* p, Json* out, std::string* error) {
  engine::RenderSettings rs;
  rs.spp = o.render.rays_per_point;
  rs.seed = o.render.seed;
  rs.pixel_filter = o.render.pixel_filter;
  foveation::ImageRgb full;
  const engine::RenderResult rr = engine::render_full(&foveart_engine_trace_rays, r.tracer.get(), r.view, rs, &full, executor);
  if (rr.status != FOVEART_RESULT_SUCCESS) return *error = "full render: engine callback failed", false;
  if (!r.metric.evaluate(full, r.reference, r.gaze, &executor, *p, *error)) return false;
  *out = {{"frame_ms", rr.trace_ms}, {"p_max", p->p_max}, {"rings_p_max", rings_p_max(*p)}};
  if (o.ring_multiples) {
    double image_multiple = 0.0;
    std::vector<double> multiples;
    if (!r.metric.threshold_multiple(full, r.reference, r.gaze, &executor, image_multiple, *error, &multiples))
      return false;
    add_ring_multiples(*p, multiples, out);
  }
  const std::string& prefix = o.render.out_prefix;
  if (prefix.empty()) return true;
  Json files = Json::array();
  if (!write_measured(prefix, "reference", r.reference, r.display, nullptr, &files, error) ||
      !write_measured(prefix, "full", full, r.display, p, &files, error))
    return false;
  (*out)["images"] = std::move(files);
  return true;
}

// One row's density: its scale, content-aware density's contrast, the rays per point's (0: off)
// and the eccentricity over which that doubles (0: off).
struct DensityAt {
  double scale = 1.0, contrast = 0.0, rays_contrast = 0.0, rays_doubling_deg = 0.0;
};

// The rows of one kind and the smallest ray fraction among its unseen ones (null: none); with an
// image prefix (--out), each row's frame and P per pixel written.
[[nodiscard]] bool sweep(const DensityProbe& probe, const char* kind, const std::vector<DensityAt>& at,
                         const PerceptualResult& full, const std::string& image_prefix,
                         const foveation::DisplayTransform& display, std::ostream& err, Json* rows, Json* best,
                         std::string* error) {
  std::vector<UnseenCandidate> candidates;
  const std::size_t first = rows->size();
  for (const DensityAt& a : at) {
    DensityProbe p = probe;
    p.options.content_rays = a.rays_contrast;
    p.options.content_rays_doubling_deg = a.rays_doubling_deg;
    DensityDetection d;
    if (!measure_density(p, a.scale, a.contrast, &d, error)) return false;
    err << kDensityWho << kind << " scale " << a.scale << " contrast " << a.contrast << " rays by contrast "
        << a.rays_contrast;
    if (a.rays_doubling_deg > 0.0) err << " doubling every " << a.rays_doubling_deg << " deg";
    err << ": rays " << d.ray_fraction << ", P max " << d.p.p_max << "\n";
    Json row = row_json(kind, d, full);
    if (!image_prefix.empty()) {
      Json files = Json::array();
      const std::string name = row_image_name(kind, a.scale, a.contrast, a.rays_contrast, a.rays_doubling_deg);
      if (!write_measured(image_prefix, name, d.image, display, &d.p, &files, error)) return false;
      row["images"] = std::move(files);
    }
    candidates.push_back({d.ray_fraction, row["unseen"].get<bool>()});
    rows->push_back(std::move(row));
  }
  const std::optional<std::size_t> i = smallest_unseen(candidates);
  *best = i ? (*rows)[first + *i] : Json();
  return true;
}

// The content-aware row (thinned by contrast, rays per point by contrast, or both) with the fewest rays
// detected no more than eccentricity-only density at the same density scale (null: none, or no
// eccentricity row at that scale).
Json fewest_at_eccentricity_detection(const Json& rows, double density_scale) {
  const auto p_of = [](const Json& row) {
    std::vector<double> v;
    for (const Json& p : row["rings_p_max"]) v.push_back(p.is_null() ? std::nan("") : p.get<double>());
    return v;
  };
  const auto baseline = std::find_if(rows.begin(), rows.end(), [&](const Json& row) {
    return row["kind"] == "eccentricity" && row["density_scale"].get<double>() == density_scale;
  });
  if (baseline == rows.end()) return Json();
  Json best;
  for (const Json& row : rows)
    if (row["kind"] != "eccentricity" && row["density_scale"] == (*baseline)["density_scale"] &&
        detected_no_more(p_of(row), p_of(*baseline)) &&
        (best.is_null() || row["ray_fraction"].get<double>() < best["ray_fraction"].get<double>()))
      best = row;
  return best;
}

}  // namespace

bool unseen_in_every_ring(const std::vector<double>& row_p_max, const std::vector<double>& full_p_max) {
  for (std::size_t r = 0; r < row_p_max.size() && r < full_p_max.size(); ++r)
    if (full_p_max[r] < 0.5 && !(row_p_max[r] < 0.5)) return false;  // NaN full: not measurable
  return true;
}

std::size_t measurable_ring_count(const std::vector<double>& full_p_max) {
  return std::size_t(std::count_if(full_p_max.begin(), full_p_max.end(), [](double p) { return p < 0.5; }));
}

std::optional<std::size_t> smallest_unseen(const std::vector<UnseenCandidate>& rows) {
  std::optional<std::size_t> best;
  for (std::size_t i = 0; i < rows.size(); ++i)
    if (rows[i].unseen && (!best || rows[i].ray_fraction < rows[*best].ray_fraction)) best = i;
  return best;
}

bool detected_no_more(const std::vector<double>& row_p_max, const std::vector<double>& baseline_p_max) {
  for (std::size_t r = 0; r < row_p_max.size() && r < baseline_p_max.size(); ++r) {
    if (std::isnan(row_p_max[r]) && std::isnan(baseline_p_max[r])) continue;
    if (!(row_p_max[r] <= baseline_p_max[r] + kSameDetectionP)) return false;  // NaN on one side: not the same
  }
  return true;
}

int run_density(const DensityOptions& options, std::ostream& out, std::ostream& err) {
  DensityOptions o = options;
  if (const std::string bad = density_problem(o); !bad.empty()) return err << kDensityWho << bad << "\n", 2;
  render_view::RenderOptions whole_view = options.render;  // the preset's view that --crop cuts from
  whole_view.size_px.reset();
  whole_view.fov = {};
  foveation::Executor executor(o.render.threads > 0 ? unsigned(o.render.threads) : 0u);
  DensityRun r;
  std::string error;
  Json baseline, rows = Json::array(), best_eccentricity, best_content, best_rays, best_both;
  PerceptualResult full;
  if (!set_up_density(o, whole_view, executor, err, &r, &error) ||
      !baseline_json(o, r, executor, &full, &baseline, &error))
    return err << kDensityWho << error << "\n", 1;
  DensityProbe probe{r.tracer.get(), r.view, r.gaze, o.render, &r.reference, &r.metric, std::nullopt, {}, &executor};
  if (!o.render.cache_dir.empty()) probe.cache_dir = std::filesystem::path(o.render.cache_dir);
  probe.log = [&](const std::string& m) { err << kDensityWho << m << "\n"; };
  probe.keep_image = !o.render.out_prefix.empty();
  probe.ring_multiples = o.ring_multiples;
  const auto run_sweep = [&](const char* kind, const std::vector<DensityAt>& at, Json* best) {
    return sweep(probe, kind, at, full, o.render.out_prefix, r.display, err, &rows, best, &error);
  };
  std::vector<DensityAt> eccentricity, content, rays, both;
  for (const double s : o.scales) eccentricity.push_back({s, 0.0, 0.0, 0.0});
  if (!run_sweep("eccentricity", eccentricity, &best_eccentricity)) return err << kDensityWho << error << "\n", 1;
  Json content_scales = {o.render.density_scale};  // and, with --content-at-unseen, the sparsest unseen scale
  if (o.content_at_unseen && !best_eccentricity.is_null() && best_eccentricity["density_scale"] != content_scales[0])
    content_scales.push_back(best_eccentricity["density_scale"]);
  for (const double s : content_scales) {
    for (const double c : o.contrasts) content.push_back({s, c, 0.0, 0.0});
    for (const double d : o.rays_doublings) {
      for (const double c : o.ray_contrasts) rays.push_back({s, 0.0, c, d});
      for (const double c : o.both_contrasts) both.push_back({s, c, c, d});
    }
  }
  if (!run_sweep("content", content, &best_content) || !run_sweep("rays", rays, &best_rays) ||
      !run_sweep("both", both, &best_both))
    return err << kDensityWho << error << "\n", 1;
  const Json report = {
      {"scene", o.render.scene},
      {"preset", o.render.preset},
      {"width", r.view.width_px},
      {"height", r.view.height_px},
      {"gaze", {r.gaze.x, r.gaze.y}},
      {"fov_deg", render_view::fov_deg(r.view)},
      {"pixels_per_deg", r.metric.display().pixels_per_deg},
      {"interpolation", o.render.interpolation},
      {"rays_per_point", o.render.rays_per_point},
      {"reference_spp", r.reference_spp},
      {"exposure", r.display.exposure},
      {"ring_edges_deg", metrics::kRingEdgesDeg},
      {"full", baseline},
      {"rows", rows},
      {"best_eccentricity", best_eccentricity},
      {"best_content", best_content},
      {"best_rays", best_rays},
      {"best_both", best_both},
      {"content_density_scales", content_scales},
      {"content_at_eccentricity_detection", fewest_at_eccentricity_detection(rows, o.render.density_scale)}};
  out << report.dump(2) << "\n";
  return 0;
}

void register_density(CLI::App& app) {
  auto o = std::make_shared<DensityOptions>();
  auto gaze = std::make_shared<std::string>(), pose = std::make_shared<std::string>(), crop = std::make_shared<std::string>();
  CLI::App* cmd = app.add_subcommand(
      "density", "The smallest ray fraction, eccentricity-only and content-aware, that the perceptual metric does not see");
  const std::shared_ptr<render_view::RenderOptions> render(o, &o->render);
  const std::function<void()> parse_common = render_view::add_render_options(cmd, render);
  add_reference_options(cmd, &o->reference, /*with_file=*/false);
  cmd->get_option("--out")->description(
      "Write each frame measured as PREFIX_<row>.png and its P per pixel as PREFIX_<row>_p.png (grey, white 1), "
      "the reference and the full render too");
  cmd->add_option("--gaze", *gaze, "Gaze X,Y in pixels of the eye image (default: centre)");
  cmd->add_option("--pose", *pose, "Where the viewer stands, X,Y,Z, or an exact eye pose px,py,pz,qx,qy,qz,qw");
  cmd->add_option("--crop", *crop, "WxH: a crop of the preset's view at its pixels per degree, around its centre");
  cmd->add_option("--scales", o->scales, "Density scales of the eccentricity-only rows")->delimiter(',')->capture_default_str();
  CLI::Option* contrasts = cmd->add_option("--contrasts", o->contrasts,
                                           "Content contrasts of the content-aware rows (at --density-scale; default "
                                           "0.25,0.5,1); --contrasts alone: none")
                               ->delimiter(',')
                               ->expected(0, CLI::detail::expected_max_vector_size);
  cmd->add_option("--ray-contrasts", o->ray_contrasts,
                  "Contrasts from which a point casts all its rays, of the rays-per-point rows (at --density-scale; "
                  "none by default)")
      ->delimiter(',')->capture_default_str();
  cmd->add_option("--both-contrasts", o->both_contrasts,
                  "Contrasts of rows that thin points and vary their rays from the same contrast (at --density-scale; "
                  "none by default)")
      ->delimiter(',')->capture_default_str();
  cmd->add_option("--rays-doublings", o->rays_doublings,
                  "Eccentricities (degrees) over which the rays and both rows' contrast doubles "
                  "(--content-rays-doubling), a row each; 0: the same contrast everywhere (default: "
                  "--content-rays-doubling's)")
      ->delimiter(',');
  cmd->add_flag("--content-at-unseen", o->content_at_unseen,
                "The content-aware rows also at the sparsest --scales density the metric does not see, where it is "
                "not --density-scale");
  cmd->add_flag("--ring-multiples", o->ring_multiples,
                "Also how many times above threshold each ring of each frame is (fovea-eval perceptual "
                "--ring-multiples; about 100 evaluations of the metric a frame)");
  cmd->add_option("--white-cd-m2", o->white_cd_m2, "Luminance of display white (cd/m^2)")->capture_default_str();
  cmd->callback([o, gaze, pose, crop, parse_common, contrasts] {
    parse_common();
    if (contrasts->count() == 1 && contrasts->results()[0].empty()) o->contrasts.clear();  // --contrasts alone
    if (!gaze->empty()) o->render.gaze_px = render_view::parse_gaze_option("--gaze", *gaze);
    if (!pose->empty()) render_view::parse_pose_option("--pose", *pose, &o->render);
    if (!crop->empty()) {
      int w = 0, h = 0;
      char end = 0;
      if (std::sscanf(crop->c_str(), "%dx%d%c", &w, &h, &end) != 2) throw CLI::ValidationError("--crop", "expected WxH, got '" + *crop + "'");
      o->crop_px = glm::ivec2(w, h);
    }
    const int code = run_density(*o, std::cout, std::cerr);
    if (code != 0) throw CLI::RuntimeError(code);
  });
}

}  // namespace foveart::eval
