// `fovea-eval pricelist`: measures every setting of the grid against a converged
// reference, in groups that share tables, frames interleaved with a full
// 1-ray-per-pixel anchor frame so that a slow spell of the machine falls on
// both; appends each setting's result to OUT/results.jsonl as it lands (a
// re-run with the same OUT skips those), then writes the price list
// (pricelist_report.hpp).
#include <eval/cmd_pricelist.hpp>

#include <eval/temporal_variants.hpp>
#include <render_view/display_options.hpp>
#include <render_view/render_cli.hpp>
#include <render_view/render_options.hpp>
#include <eval/lab_options.hpp>
#include <eval/pfm.hpp>
#include <eval/full_history.hpp>
#include <eval/perceptual_metric.hpp>
#include <eval/pricelist_report.hpp>
#include <eval/reference.hpp>
#include <metrics/comparison_json.hpp>
#include <eval/results_jsonl.hpp>

#include <engine/gltf_loader.hpp>
#include <engine/render.hpp>
#include <engine/tracer.hpp>

#include <metrics/csf_error.hpp>
#include <foveation/executor.hpp>
#include <foveation/foveated_view.hpp>
#include <metrics/image_metrics.hpp>

#include <toolkit/image_io.hpp>
#include <toolkit/machine.hpp>
#include <toolkit/outputs.hpp>
#include <toolkit/progress.hpp>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>

namespace foveart::eval {
namespace {

using Json = nlohmann::ordered_json;
namespace fs = std::filesystem;

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

Json rays_with_total_json(const engine::RayCounts& c) {
  return Json{{"primary", c.primary}, {"shadow", c.shadow}, {"reflection", c.reflection},
              {"refraction", c.refraction}, {"total", c.total()}};
}

// One setting being measured: its view (foveated), its history (full with the image history) or
// render settings (full), per-frame stage times, rays of its first frame, flicker so far.
struct Measure {
  PriceSetting setting;
  std::unique_ptr<foveation::FoveatedView> view;
  std::unique_ptr<FullHistoryRender> full_history;
  foveation::ImageRgb full_image;
  std::vector<double> select_ms, trace_ms, reconstruct_ms, temporal_ms, density_ms, total_ms;
  engine::RayCounts rays;
  std::uint32_t points = 0;
  foveation::ImageRgb previous_display;
  std::array<double, metrics::kRingCount> flicker_sum{};
  int flicker_pairs = 0;
  int frames_wanted = 0;
  int frames_done = 0;
};

struct Context {
  const PricelistOptions& o;
  engine::Tracer& tracer;
  FoveartEyeView view;
  glm::vec2 gaze;
  foveation::Executor& executor;
  const metrics::EccentricityMap& map;
  const foveation::ImageRgb& reference_display;
  std::ostream& err;
  float exposure = 1.0f;  // what the display values scale radiance by (render_display)
  const PerceptualMetric* perceptual = nullptr;
  // The full render's display values (its last frame) per rays per pixel: the perceptual
  // columns' baseline for every row at that count.
  std::map<int, foveation::ImageRgb> full_display;
  mutable std::map<int, PerceptualResult> full_perceptual;  // each full_display's against the reference
  std::size_t resumed = 0;  // settings of the grid measured by earlier runs (results.jsonl)
};

render_view::RenderOptions render_options_of(const PricelistOptions& o, const PriceSetting* s) {
  render_view::RenderOptions r;
  r.scene = o.scene;
  r.preset = o.preset;
  r.eye = o.eye;
  r.size_px = o.size_px;
  r.gaze_px = o.gaze_px;
  r.viewer_m = o.viewer_m;
  r.look_at_m = o.look_at_m;
  r.exposure = o.exposure;
  r.seed = o.seed;
  r.pixel_filter = o.pixel_filter;
  if (s != nullptr && !s->full) {
    r.mode = "foveated";
    r.interpolation = s->interpolation;
    r.k = s->k;
    r.density_scale = s->density_scale;
    r.pattern = s->pattern;
    r.rays_per_point = s->rays_per_point;
    r.content_contrast = s->content_contrast;
    r.content_rays = s->content_rays;
  }
  return r;
}

// The time anchor: the full render at 1 ray per pixel without history.
bool is_anchor(const PriceSetting& s) { return s.full && !s.history && s.rays_per_point == 1; }

// A setting's view settings at a still view: the image history (when it has it) converges over
// frames of new jitter; the full render with history takes the same (FullHistoryRender).
foveation::ViewSettings still_view_settings(const PricelistOptions& o, const PriceSetting& s) {
  return variant_view_settings(s.history ? TemporalVariant::image : TemporalVariant::off,
                               {s.rays_per_point, o.seed, o.pixel_filter, /*mean_while_young=*/false});
}

// One frame of a setting; false with a message on failure.
[[nodiscard]] bool render_frame(Context& c, Measure& m, int round, std::string* error) {
  const engine::RayCounts before = c.tracer.counts();
  const foveation::ImageRgb* image = nullptr;
  if (m.full_history) {
    const FullHistoryFrame f = m.full_history->render(&foveart_engine_trace_rays, &c.tracer, c.view, c.gaze,
                                              std::uint64_t(round), c.executor);
    if (f.status != FOVEART_RESULT_SUCCESS) {
      *error = m.setting.id() + ": engine callback failed with status " + std::to_string(f.status);
      return false;
    }
    m.select_ms.push_back(0.0);
    m.trace_ms.push_back(f.trace_ms);
    m.reconstruct_ms.push_back(0.0);
    m.temporal_ms.push_back(f.temporal_ms);
    m.total_ms.push_back(f.trace_ms + f.temporal_ms);
    m.points = c.view.width_px * c.view.height_px;
    image = &m.full_history->image();
  } else if (m.setting.full) {
    engine::RenderSettings rs;
    rs.spp = m.setting.rays_per_point;
    // The same jitter every frame, as the foveated frames without history and as the
    // pixel-grid fovea (foveation::pixel_jitter with the same seed): inside the
    // fovea a full frame and a pixel-grid frame trace the same rays.
    rs.seed = c.o.seed;
    rs.pixel_filter = c.o.pixel_filter;
    const engine::RenderResult rr =
        engine::render_full(&foveart_engine_trace_rays, &c.tracer, c.view, rs, &m.full_image, c.executor);
    if (rr.status != FOVEART_RESULT_SUCCESS) {
      *error = m.setting.id() + ": engine callback failed with status " + std::to_string(rr.status);
      return false;
    }
    m.select_ms.push_back(0.0);
    m.trace_ms.push_back(rr.trace_ms);
    m.reconstruct_ms.push_back(0.0);
    m.temporal_ms.push_back(0.0);
    m.total_ms.push_back(rr.trace_ms);
    m.points = c.view.width_px * c.view.height_px;
    image = &m.full_image;
  } else {
    foveation::FrameRequest request;
    request.view = c.view;
    request.gaze_px = c.gaze;
    request.frame_index = std::uint64_t(round);
    const foveation::FrameResult fr = m.view->render(request, &foveart_engine_trace_rays, &c.tracer, c.executor);
    if (!fr.ok()) {
      *error = m.setting.id() + ": " + fr.message;
      return false;
    }
    m.select_ms.push_back(fr.select_ms);
    m.trace_ms.push_back(fr.trace_ms);
    m.reconstruct_ms.push_back(fr.reconstruct_ms);
    m.temporal_ms.push_back(fr.temporal_ms);
    m.density_ms.push_back(fr.density_ms);
    m.total_ms.push_back(fr.select_ms + fr.trace_ms + fr.reconstruct_ms + fr.temporal_ms);
    m.points = fr.points;
    image = &m.view->image();
  }
  m.rays = c.tracer.counts() - before;  // the last frame's: content-aware density thins from the second on
  foveation::ImageRgb display = metrics::display_encode(*image, c.exposure);
  if (m.frames_done > 0) {
    const auto mse = metrics::ring_mse(m.previous_display, display, c.map);
    for (std::size_t r = 0; r < mse.size(); ++r) m.flicker_sum[r] += std::isnan(mse[r]) ? 0.0 : mse[r];
    ++m.flicker_pairs;
  }
  m.previous_display = std::move(display);
  ++m.frames_done;
  return true;
}

// The error heat map of a setting: the CSF-weighted error of every pixel as a
// full-size PNG, black (0) through red and yellow to white (the 99th
// percentile, returned in *scale_out, and above). False and *error when it cannot be written.
[[nodiscard]] bool write_heatmap(const Context& c, const foveation::ImageRgb& display, const fs::path& file,
                                 double* scale_out, std::string* error) {
  const std::vector<float> e = metrics::csf_error_map(c.reference_display, display, c.map);
  std::vector<float> sorted = e;
  const std::size_t p99 = sorted.size() * 99 / 100;
  std::nth_element(sorted.begin(), sorted.begin() + std::ptrdiff_t(p99), sorted.end());
  const double scale = std::max(1e-6, double(sorted[p99]));
  *scale_out = scale;
  std::vector<std::uint8_t> rgb(e.size() * 3);
  for (std::size_t i = 0; i < e.size(); ++i) {
    const double t = std::clamp(double(e[i]) / scale, 0.0, 1.0) * 3.0;  // 0-1 red, 1-2 yellow, 2-3 white
    rgb[i * 3] = std::uint8_t(std::lround(255.0 * std::min(1.0, t)));
    rgb[i * 3 + 1] = std::uint8_t(std::lround(255.0 * std::clamp(t - 1.0, 0.0, 1.0)));
    rgb[i * 3 + 2] = std::uint8_t(std::lround(255.0 * std::clamp(t - 2.0, 0.0, 1.0)));
  }
  return toolkit::write_png_u8(file.string(), c.map.width_px, c.map.height_px, 3, rgb, error);
}

// The full render's at `rays_per_pixel` detection probability against the reference, evaluated once;
// null (and *error, or empty when its image is not at hand) when it cannot be.
const PerceptualResult* baseline_perceptual(const Context& c, int rays_per_pixel, std::string* error) {
  if (const auto done = c.full_perceptual.find(rays_per_pixel); done != c.full_perceptual.end()) return &done->second;
  const auto full = c.full_display.find(rays_per_pixel);
  PerceptualResult p;
  if (full == c.full_display.end() || !c.perceptual->evaluate(full->second, c.reference_display, c.gaze, &c.executor, p, *error))
    return nullptr;
  return &c.full_perceptual.emplace(rays_per_pixel, std::move(p)).first->second;
}

// The perceptual metric's detection probability of the row's last frame against the converged
// reference, beside the same for the full render at the same rays per pixel (full_spp<r>, the
// baseline): what the row shows that the full render at its rays does not is what foveation adds
// (docs/lab/perceptual_metric.md). Per ring (rings[r].p_detect_mean, _share = the share of pixels
// at P >= 0.5, _max; p_detect_full_* the baseline's) and over the image. Null where the metric or
// the baseline's image is not at hand.
void add_perceptual(const Context& c, const PriceSetting& s, const foveation::ImageRgb& last, Json& j) {
  const std::string baseline = "full_spp" + std::to_string(s.rays_per_point);
  j["p_detect_against"] = "reference";
  j["p_detect_baseline"] = baseline;
  PerceptualResult p;
  std::string error;
  const bool ok = c.perceptual != nullptr && c.perceptual->evaluate(last, c.reference_display, c.gaze, &c.executor, p, error);
  const PerceptualResult* full = ok ? baseline_perceptual(c, s.rays_per_point, &error) : nullptr;
  if (c.perceptual != nullptr && (!ok || full == nullptr))
    c.err << "fovea-eval pricelist: " << s.id() << ": " << (ok ? "no baseline perceptual columns (" : "no perceptual columns (")
          << (error.empty() ? baseline + "'s image is not at hand" : error) << ")\n";
  const auto put = [&j](const std::string& prefix, const PerceptualResult* r) {
    j[prefix + "mean"] = r != nullptr ? Json(r->p_mean) : Json();
    j[prefix + "share"] = r != nullptr ? Json(r->detected_fraction) : Json();
    j[prefix + "max"] = r != nullptr ? Json(r->p_max) : Json();
  };
  put("p_detect_", ok ? &p : nullptr);
  put("p_detect_full_", full);
  for (std::size_t r = 0; r < metrics::kRingCount; ++r) {
    const bool has = ok && p.rings[r].pixels > 0;
    Json& ring = j["rings"][r];
    ring["p_detect_mean"] = has ? Json(p.rings[r].p_mean) : Json();
    ring["p_detect_share"] = has ? Json(p.rings[r].detected_fraction) : Json();
    ring["p_detect_max"] = has ? Json(p.rings[r].p_max) : Json();
    ring["p_detect_full_mean"] = has && full ? Json(full->rings[r].p_mean) : Json();
    ring["p_detect_full_share"] = has && full ? Json(full->rings[r].detected_fraction) : Json();
    ring["p_detect_full_max"] = has && full ? Json(full->rings[r].p_max) : Json();
  }
}

Json result_json(const Context& c, Measure& m, double anchor_ms, const fs::path& out_dir, bool write_image,
                 bool heatmap, std::string* error) {
  const PriceSetting& s = m.setting;
  const foveation::ImageRgb& last = m.previous_display;  // display values of the last frame
  const metrics::ImageComparison cmp = metrics::compare_images(c.reference_display, last, c.map);
  Json j = {{"id", s.id()}, {"kind", s.full ? "full" : "foveated"}, {"spp", s.rays_per_point}};
  if (!s.full) {
    j["method"] = s.interpolation;
    j["k"] = s.k;
    j["scale"] = s.density_scale;
    j["pattern"] = s.pattern;
    j["content_contrast"] = s.content_contrast;
    j["content_rays"] = s.content_rays;
  }
  j["temporal"] = s.history ? "image" : "off";
  j["points"] = m.points;
  j["rays"] = rays_with_total_json(m.rays);
  // Primary rays of the last frame against the full render's at the same rays per pixel.
  const double full_rays = double(c.view.width_px) * double(c.view.height_px) * double(s.rays_per_point);
  j["ray_fraction"] = full_rays > 0.0 ? double(m.rays.primary) / full_rays : 0.0;
  // The frame whose total is the median, so that the stages add up to the total.
  std::vector<std::size_t> order(m.total_ms.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return m.total_ms[a] < m.total_ms[b]; });
  const std::size_t med = order[order.size() / 2];
  j["ms"] = {{"select", m.select_ms[med]}, {"trace", m.trace_ms[med]}, {"reconstruct", m.reconstruct_ms[med]},
             {"temporal", m.temporal_ms[med]}, {"total", m.total_ms[med]}};
  if (!s.full) j["ms"]["density"] = m.density_ms[med];  // content-aware density's part of select and trace
  j["frames_total_ms"] = m.total_ms;
  j["anchor_full_ms"] = anchor_ms;
  j["time_fraction"] = anchor_ms > 0.0 ? m.total_ms[med] / anchor_ms : 0.0;
  const Json cj = metrics::comparison_json(cmp);
  j["psnr"] = cj["psnr"];
  j["ssim"] = cj["ssim"];
  j["csf_rmse"] = cj["csf_rmse"];
  j["rings"] = cj["rings"];
  for (std::size_t r = 0; r < metrics::kRingCount; ++r)
    j["rings"][r]["flicker"] = m.flicker_pairs > 0 ? std::sqrt(m.flicker_sum[r] / m.flicker_pairs) : 0.0;
  j["flicker_frames"] = m.frames_done;
  add_perceptual(c, s, last, j);
  if (write_image) {
    const fs::path file = out_dir / "images" / (s.id() + ".pfm");
    if (!write_pfm(file.string(), last, error)) return {};
    if (!toolkit::write_png((out_dir / "images" / (s.id() + ".png")).string(), last, toolkit::PngValues::display,
                            error))
      return {};
    j["image"] = fs::relative(file, out_dir).string();
  }
  if (heatmap) {
    double scale = 0.0;
    if (!write_heatmap(c, last, out_dir / "heatmap.png", &scale, error)) return {};
    j["heatmap"] = {{"file", "heatmap.png"}, {"white_at_csf_error", scale}};
  }
  return j;
}

// Measures one group of settings (all full renders, or all settings on one
// set of tables) and appends each result to results.jsonl.
[[nodiscard]] bool run_group(Context& c, std::vector<PriceSetting> settings, const fs::path& out_dir,
                             std::ofstream& results, const std::string& heatmap_id, toolkit::Progress& progress,
                             double* done, double total, std::map<std::string, Json>* all) {
  std::string error;
  std::vector<Measure> ms(settings.size());
  std::shared_ptr<const foveation::ViewTables> tables;
  for (std::size_t i = 0; i < settings.size(); ++i) {
    Measure& m = ms[i];
    m.setting = settings[i];
    m.frames_wanted = m.setting.history ? std::max(c.o.history_frames, 2) : c.o.frames;
    if (m.setting.full) {
      if (m.setting.history) m.full_history = std::make_unique<FullHistoryRender>(still_view_settings(c.o, m.setting));
      continue;
    }
    if (!tables) {
      const render_view::RenderOptions ro = render_options_of(c.o, &m.setting);
      tables = render_view::load_foveated_tables(ro, c.view, fs::path(c.o.cache_dir), c.executor,
                                    [&](const std::string& msg) { c.err << "fovea-eval pricelist: " << msg << "\n"; },
                                    &error);
      if (!tables) {
        c.err << "fovea-eval pricelist: " << m.setting.id() << ": " << error << "\n";
        return false;
      }
    }
    foveation::ViewSettings vs = still_view_settings(c.o, m.setting);
    vs.content_density.full_contrast = float(m.setting.content_contrast);
    vs.content_density.rays_contrast = float(m.setting.content_rays);
    vs.content_density.exposure = c.exposure;
    m.view = std::make_unique<foveation::FoveatedView>(tables, vs);
  }
  // The anchor: a full frame at 1 ray per pixel in every round (the group's own full_spp1 when it has it:
  // a resumed full group may hold only full renders with history).
  const bool anchor_in_group = std::any_of(settings.begin(), settings.end(), is_anchor);
  Measure anchor_frames;
  anchor_frames.setting.full = true;
  std::vector<double> anchor_ms;
  int rounds = 0;
  for (const Measure& m : ms) rounds = std::max(rounds, m.frames_wanted);
  for (int round = 0; round < rounds; ++round) {
    if (!anchor_in_group && round < c.o.frames) {
      if (!render_frame(c, anchor_frames, round, &error)) break;
      anchor_ms.push_back(anchor_frames.total_ms.back());
    }
    for (Measure& m : ms) {
      if (round >= m.frames_wanted) continue;
      if (!render_frame(c, m, round, &error)) break;
      if (is_anchor(m.setting)) anchor_ms.push_back(m.total_ms.back());
      *done += 1.0;
      progress.update(*done / total);
    }
    if (!error.empty()) break;
  }
  if (!error.empty()) {
    c.err << "fovea-eval pricelist: " << error << "\n";
    return false;
  }
  const double anchor = median(anchor_ms);
  for (Measure& m : ms)
    if (m.setting.full && !m.setting.history) c.full_display[m.setting.rays_per_point] = m.previous_display;
  for (Measure& m : ms) {
    const std::string id = m.setting.id();
    // The full renders without history always: a resumed run's perceptual columns compare with them.
    const bool image = c.o.images || id == heatmap_id || (m.setting.full && !m.setting.history);
    Json j = result_json(c, m, anchor, out_dir, image, id == heatmap_id, &error);
    if (!error.empty()) {
      c.err << "fovea-eval pricelist: " << error << "\n";
      return false;
    }
    results << j.dump() << "\n";
    results.flush();
    (*all)[id] = std::move(j);  // id is a copy taken above
  }
  return true;
}

// report.md copied to `file`, its relative links (images) pointing into out_dir from there.
std::string write_md_copy(const fs::path& out_dir, const fs::path& file) {
  std::ifstream in(out_dir / "report.md");
  std::stringstream text;
  text << in.rdbuf();
  if (!in) return "cannot read " + (out_dir / "report.md").string();
  const fs::path parent = fs::absolute(file).parent_path();
  std::error_code ec;
  fs::create_directories(parent, ec);
  std::string prefix = fs::relative(fs::absolute(out_dir), parent, ec).generic_string();
  if (ec || prefix.empty()) prefix = fs::absolute(out_dir).generic_string();
  const std::string src = text.str();
  std::string md;
  for (std::size_t i = 0; i < src.size();) {
    const std::size_t at = src.find("](", i);
    if (at == std::string::npos) {
      md += src.substr(i);
      break;
    }
    md += src.substr(i, at + 2 - i);
    i = at + 2;
    if (src.compare(i, 4, "http") != 0 && src.compare(i, 1, "#") != 0) md += prefix + "/";
  }
  std::ofstream out(file);
  out << md;
  if (!out) return "cannot write " + file.string();
  return "";
}

constexpr const char* kPricelistWho = "fovea-eval pricelist: ";
// The setting the headline calls the thesis's default, and the default of --heatmap.
constexpr const char* kThesisDefault = "nearest_k1_s1_thesis_r1";

// The full render (without history) at every rays per point a row of the grid has, added after the
// full renders when the grid lacks it: the perceptual columns compare each row with it.
void add_equal_spp_full_renders(std::vector<PriceSetting>* settings) {
  std::vector<int> have, want;
  for (const PriceSetting& s : *settings) (s.full && !s.history ? have : want).push_back(s.rays_per_point);
  std::sort(want.begin(), want.end());
  want.erase(std::unique(want.begin(), want.end()), want.end());
  auto at = std::find_if(settings->begin(), settings->end(), [](const PriceSetting& s) { return !s.full || s.history; });
  for (const int r : want) {
    if (std::find(have.begin(), have.end(), r) != have.end()) continue;
    PriceSetting full;
    full.full = true;
    full.rays_per_point = r;
    at = settings->insert(at, full) + 1;
  }
}

// What is wrong with the options before any work ("" when nothing), the grid's settings into *settings.
std::string options_problem(const PricelistOptions& o, std::vector<PriceSetting>* settings) {
  if (o.out_dir.empty()) return "--out DIR is required";
  if (o.frames < 1 || o.frames > 100) return "--frames must be in 1..100";
  if (o.history_frames < 2 || o.history_frames > 100) return "--history-frames must be in 2..100";
  std::string bad;
  if (!expand_grid(o.grid, settings, &bad)) return "bad grid: " + bad;
  add_equal_spp_full_renders(settings);
  if (!(o.white_cd_m2 > 0.0) || !std::isfinite(o.white_cd_m2)) return "--white-cd-m2 must be a positive luminance";
  if (o.reference_spp.empty()) return "--reference-spp must be auto or rays per pixel";
  if (!render_view::check_render_options(render_options_of(o, nullptr), &bad) ||
      !check_reference_choice(ReferenceChoice{o.reference_spp, "", ""}, &bad) ||
      !check_temporal_options(o.temporal, &bad))
    return bad;
  if (std::none_of(settings->begin(), settings->end(), is_anchor))
    return "the full-render baseline must include 1 ray per pixel (the time anchor)";
  if (!toolkit::check_writable_dir((fs::path(o.out_dir) / "images").string(), &bad)) return "--out: " + bad;
  if (!o.md_file.empty()) {  // its folder is made, as for --out
    const fs::path folder = fs::absolute(o.md_file).parent_path();
    if (!toolkit::check_writable_dir(folder.string(), &bad) || !toolkit::check_writable_file(o.md_file, &bad))
      return "--md: " + bad;
  }
  return "";
}

// The scene, its tracer, the view and gaze measured, and its display transform: the whole run's.
struct PriceScene {
  std::unique_ptr<engine::Tracer> tracer;
  std::uint64_t hash = 0;
  FoveartEyeView view{};
  glm::vec2 gaze{};
  foveation::DisplayTransform display;
};

[[nodiscard]] bool set_up_scene(const PricelistOptions& o, foveation::Executor& executor, PriceScene* s,
                                std::string* error) {
  engine::LoadResult loaded = engine::load_scene(o.scene);
  if (!loaded.ok()) {
    *error = loaded.error;
    return false;
  }
  s->tracer = engine::Tracer::create(std::move(*loaded.scene), {}, error);
  if (!s->tracer) return false;
  s->hash = rendered_scene_hash(*s->tracer);
  const render_view::RenderOptions base = render_options_of(o, nullptr);
  s->view = render_view::eye_view(base, s->tracer->scene());
  s->gaze = o.gaze_px.value_or(glm::vec2(0.5f * float(s->view.width_px), 0.5f * float(s->view.height_px)));
  const std::optional<foveation::DisplayTransform> display =
      render_view::render_display(base, *s->tracer, s->view, executor, error);
  if (!display) return false;
  s->display = *display;
  return true;
}

// What an output directory measures: a different run must not resume into it.
Json run_json(const PricelistOptions& o, const PriceScene& s) {
  const FoveartEyeView& v = s.view;
  Json run = {{"scene", s.tracer->scene().source},
              {"scene_hash", s.hash},
              {"width", v.width_px},
              {"height", v.height_px},
              {"eye", o.eye},
              {"preset", o.preset},
              {"gaze", {s.gaze.x, s.gaze.y}},
              {"reference_spp", o.reference_spp},
              {"frames", o.frames},
              {"history_frames", o.history_frames},
              {"seed", o.seed},
              {"pixel_filter", foveation::pixel_filter_name(o.pixel_filter)},
              {"temporal", temporal_run_json(o.temporal, o.quick)}};
  if (o.viewer_m || o.look_at_m)
    run["viewer_pose"] = {v.position_m[0],        v.position_m[1],        v.position_m[2],       v.orientation_xyzw[0],
                          v.orientation_xyzw[1], v.orientation_xyzw[2], v.orientation_xyzw[3]};
  if (s.display.exposure != 1.0f) run["exposure"] = s.display.exposure;
  if (o.white_cd_m2 != 100.0) run["white_cd_m2"] = o.white_cd_m2;  // the perceptual columns' display
  return run;
}

// The perceptual metric's display: the view's pixels per degree at the gaze, --white-cd-m2, the eye.
PerceptualDisplay perceptual_display(const PricelistOptions& o, const metrics::EccentricityMap& map) {
  PerceptualDisplay d = view_display(map, o.eye == "left" ? Eye::kLeft : Eye::kRight);
  d.white_luminance_cd_m2 = o.white_cd_m2;
  d.input = PerceptualInput::kSrgbEncoded;  // the rows' images are metrics::display_encode's
  return d;
}

// OUT/run.json: written on the first run; a re-run resumes only the same run. False and *error.
[[nodiscard]] bool claim_out_dir(const Json& run, const fs::path& out_dir, std::string* error) {
  const fs::path run_file = out_dir / "run.json";
  if (!fs::exists(run_file)) {
    std::ofstream f(run_file);
    f << run.dump(2) << "\n";
    if (!f) *error = "cannot write " + run_file.string();
    return static_cast<bool>(f);
  }
  std::ifstream in(run_file);
  const Json old = Json::parse(in, nullptr, false);
  if (!old.is_discarded() && old == run) return true;
  *error = run_file.string() +
           " describes another run (scene, view, gaze, reference or frames differ, or it is unreadable); "
           "use another --out or delete it";
  return false;
}

// The converged reference of the view (reference.hpp), cached under CACHE/reference.
std::optional<Reference> measure_reference(const PricelistOptions& o, const PriceScene& s,
                                           foveation::Executor& executor, std::ostream& err, std::string* error) {
  ReferenceOptions ro;
  if (o.reference_spp != "auto") ro.spp = std::stoi(o.reference_spp);  // checked by check_reference_choice
  ro.baseline_spp = *std::max_element(o.grid.full_rays_per_point.begin(),
                                      o.grid.full_rays_per_point.end());  // the best full render measured
  ro.seed = o.seed;
  ro.pixel_filter = o.pixel_filter;
  ro.cache_dir = (fs::path(o.cache_dir) / "reference").string();
  err << kPricelistWho << "reference (" << o.reference_spp << " rays per pixel) of " << s.view.width_px << "x"
      << s.view.height_px << "...\n";
  return converged_reference(&foveart_engine_trace_rays, s.tracer.get(), s.hash, s.view, s.gaze, ro, executor,
                             [&](const std::string& m) { err << kPricelistWho << m << "\n"; }, error);
}

// OUT/images: the reference in display values (PFM and PNG) and the eccentricity map (PFM: eccentricity
// in degrees, ring index, pixels per degree), once. False and *error naming the file.
[[nodiscard]] bool write_reference_images(const fs::path& out_dir, const foveation::ImageRgb& reference_display,
                                          const metrics::EccentricityMap& map, std::string* error) {
  const fs::path images = out_dir / "images";
  if (fs::exists(images / "reference.pfm")) return true;
  foveation::ImageRgb ecc(map.width_px, map.height_px);
  for (std::size_t i = 0; i < map.ring.size(); ++i) {
    ecc.rgb[i * 3] = map.eccentricity_deg[i];
    ecc.rgb[i * 3 + 1] = float(map.ring[i]);
    ecc.rgb[i * 3 + 2] = map.pixels_per_deg[i];
  }
  return write_pfm((images / "reference.pfm").string(), reference_display, error) &&
         toolkit::write_png((images / "reference.png").string(), reference_display, toolkit::PngValues::display,
                            error) &&
         write_pfm((images / "eccentricity.pfm").string(), ecc, error);
}

// Measures every setting not yet in OUT/results.jsonl, in groups in grid order (the full renders,
// then one per set of tables), into *done_results too. False with the problem on c.err.
[[nodiscard]] bool measure_settings(Context& c, const std::vector<PriceSetting>& settings, const fs::path& out_dir,
                                    std::chrono::steady_clock::time_point t_start,
                                    std::map<std::string, Json>* done_results) {
  const fs::path results_file = out_dir / "results.jsonl";
  *done_results = read_results_jsonl(results_file, c.err);
  c.resumed = std::size_t(std::count_if(settings.begin(), settings.end(),
                                        [&](const PriceSetting& s) { return done_results->count(s.id()) > 0; }));
  for (const PriceSetting& s : settings)  // measured before: their images (result_json wrote them)
    if (s.full && !s.history && done_results->count(s.id())) {
      foveation::ImageRgb image;
      std::string ignored;
      if (read_pfm((out_dir / "images" / (s.id() + ".pfm")).string(), &image, &ignored))
        c.full_display[s.rays_per_point] = std::move(image);
    }
  std::ofstream results(results_file, std::ios::app);
  if (!results) {
    c.err << kPricelistWho << "cannot write " << results_file.string() << "\n";
    return false;
  }
  std::vector<std::string> group_order;
  std::map<std::string, std::vector<PriceSetting>> groups;
  double total_frames = 0.0;
  for (const PriceSetting& s : settings) {
    if (done_results->count(s.id())) continue;
    if (!groups.count(s.table_id())) group_order.push_back(s.table_id());
    groups[s.table_id()].push_back(s);
    total_frames += s.history ? c.o.history_frames : c.o.frames;
  }
  c.err << kPricelistWho << settings.size() << " settings in the grid, " << done_results->size()
        << " already measured in " << results_file.string() << "\n";
  const std::string heatmap_id = c.o.heatmap.empty() ? kThesisDefault : c.o.heatmap;
  toolkit::Progress progress("pricelist");
  double done = 0.0;
  for (std::size_t g = 0; g < group_order.size(); ++g) {
    const std::vector<PriceSetting>& group = groups[group_order[g]];
    if (!run_group(c, group, out_dir, results, heatmap_id, progress, &done, total_frames, done_results)) return false;
    c.err << kPricelistWho << "[" << g + 1 << "/" << group_order.size() << "] " << group_order[g] << " measured ("
          << group.size() << " settings, "
          << std::lround(std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count()) << " s)\n";
  }
  return true;
}

// The reference as the report reads it: its count, convergence, cache and residual PSNR per ring.
Json reference_json(const Reference& r, const metrics::EccentricityMap& map) {
  Json j = {{"spp", r.spp}, {"spp_tried", r.tried_spp}, {"converged", r.converged},
            {"db_per_doubling", r.db_per_doubling}, {"from_cache", r.from_cache},
            {"cache_file", r.cache_file}, {"render_ms", r.render_ms}, {"image", "images/reference.pfm"}};
  Json residual = Json::array();
  for (double mse : r.residual_mse(map)) residual.push_back(metrics::number_or_null_json(metrics::psnr_of_mse(mse)));
  j["residual_psnr"] = residual;
  return j;
}

// The price list's files from the measured settings (in grid order), --md's copy, and the headline on `out`.
[[nodiscard]] bool write_outputs(const PricelistOptions& o, const fs::path& out_dir, const PricelistContext& pc,
                                 const std::vector<PriceSetting>& settings, std::map<std::string, Json>& done_results,
                                 std::ostream& out, std::string* error) {
  std::vector<Json> ordered;
  for (const PriceSetting& s : settings)
    if (done_results.count(s.id())) ordered.push_back(done_results[s.id()]);
  std::string headline;
  if (!write_pricelist(out_dir, pc, ordered, &headline, error)) return false;
  if (!o.md_file.empty()) {
    if (const std::string e = write_md_copy(out_dir, o.md_file); !e.empty()) {
      *error = "--md: " + e;
      return false;
    }
  }
  out << headline << "\n";
  return true;
}

}  // namespace

int run_pricelist(const PricelistOptions& o_in, std::ostream& out, std::ostream& err) {
  PricelistOptions o = o_in;
  if (o.quick) o.grid = quick_grid();
  std::vector<PriceSetting> settings;
  if (const std::string bad = options_problem(o, &settings); !bad.empty()) {
    err << kPricelistWho << bad << "\n";
    return 2;
  }
  const auto fail = [&](const std::string& message) {
    if (!message.empty()) err << kPricelistWho << message << "\n";
    return 1;
  };
  const fs::path out_dir(o.out_dir);
  if (o.cache_dir.empty()) o.cache_dir = (out_dir / "cache").string();
  const auto t_start = std::chrono::steady_clock::now();
  foveation::Executor executor(static_cast<unsigned>(std::max(0, o.threads)));
  PriceScene s;
  std::string error;
  if (!set_up_scene(o, executor, &s, &error)) return fail(error);
  const Json run = run_json(o, s);
  if (!claim_out_dir(run, out_dir, &error)) return fail(error);
  const metrics::EccentricityMap map = metrics::eccentricity_map(s.view, s.gaze);
  const std::optional<Reference> reference = measure_reference(o, s, executor, err, &error);
  if (!reference) return fail(error);
  const foveation::ImageRgb reference_display = metrics::display_encode(reference->image, s.display.exposure);
  if (!write_reference_images(out_dir, reference_display, map, &error)) return fail(error);
  Context c{o, *s.tracer, s.view, s.gaze, executor, map, reference_display, err, s.display.exposure, nullptr, {}, {}};
  PerceptualMetric perceptual;
  const PerceptualDisplay pd = perceptual_display(o, map);
  if (!PerceptualMetric::create(pd, s.view.width_px, s.view.height_px, {}, perceptual, error, &executor))
    return fail(error);
  c.perceptual = &perceptual;
  std::map<std::string, Json> done_results;
  if (!measure_settings(c, settings, out_dir, t_start, &done_results)) return fail("");
  PricelistContext pc;
  if (o.temporal.motion != "none") {
    TemporalContext tc{o.temporal, o.quick, o.scene, o.preset, o.eye, o.seed, o.pixel_filter, o.cache_dir, out_dir};
    std::optional<Json> t = run_pricelist_temporal(tc, settings, *s.tracer, s.hash, executor, err);
    if (!t) return fail("");
    pc.temporal = std::move(*t);
  }
  pc.run = run;
  pc.run["machine"] = toolkit::machine_description();
  pc.run["threads"] = executor.thread_count();
  pc.run["quick"] = o.quick;
  if (c.resumed > 0) pc.run["resumed_settings"] = c.resumed;
  pc.run["perceptual_display"] = {{"pixels_per_deg", pd.pixels_per_deg},
                                  {"white_cd_m2", pd.white_luminance_cd_m2},
                                  {"black_cd_m2", pd.black_luminance_cd_m2}};
  pc.run["run_s"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  pc.reference = reference_json(*reference, map);
  pc.thesis_default = kThesisDefault;
  pc.heatmap = o.heatmap.empty() ? kThesisDefault : o.heatmap;
  pc.command = !o.command.empty()                 ? o.command
               : !toolkit::command_line().empty() ? toolkit::command_line()
                                                  : "fovea-eval pricelist";
  if (!write_outputs(o, out_dir, pc, settings, done_results, out, &error)) return fail(error);
  return 0;
}

namespace {

template <class T>
std::string parse_numbers(const std::string& text, std::vector<T>* out) {
  std::vector<std::string> items;
  if (!split_list(text, &items)) return "expected a comma-separated list";
  out->clear();
  for (const std::string& i : items) {
    std::istringstream in(i);
    T v{};
    if (!(in >> v) || !(in >> std::ws).eof()) return "'" + i + "' is not a number";
    out->push_back(v);
  }
  return "";
}

// A list of numbers, or "none" (empty).
std::string list_or_none(const std::string& text, std::vector<double>* out) {
  if (text != "none") return parse_numbers(text, out);
  out->clear();
  return "";
}

// The options given as text, parsed once the command line is read.
struct PricelistTexts {
  std::string gaze, size, viewer, look_at, temporal_size;
  std::array<std::string, 8> lists;  // the grid lists, in kGridListOptions' order
};

constexpr const char* kGridListOptions[] = {"--full-rays-per-point", "--interpolation", "--density-scale",
                                            "--rays-per-point",      "--pattern",       "--history-rays-per-point",
                                            "--content-contrast",    "--content-rays"};

// The view: scene, display, eye, viewer, gaze and exposure.
void add_view_options(CLI::App* cmd, PricelistOptions& o, PricelistTexts& t) {
  cmd->add_option("--scene", o.scene, "glTF/GLB file, or 'default'")->capture_default_str();
  cmd->add_option("--preset", o.preset, "Display preset")->capture_default_str();
  cmd->add_option("--eye", o.eye, "left or right")->capture_default_str();
  cmd->add_option("--gaze", t.gaze, "Gaze X,Y in pixels (default: centre)");
  cmd->add_option("--pose", t.viewer,
                  "Where the viewer stands, X,Y,Z (metres, scene space; default the scene's camera)");
  cmd->add_option("--look-at", t.look_at, "Turn the viewer to face this point X,Y,Z");
  cmd->add_option("--exposure", o.exposure,
                  "Linear exposure of the display values the metrics compare, or auto (a pre-pass of the view)")
      ->capture_default_str();
  cmd->add_option("--size", t.size, "Per-eye size WxH in pixels (the preset's horizontal FOV kept)");
}

// Where the results go, the reference, frames, threads and what else is written.
void add_run_options(CLI::App* cmd, PricelistOptions& o) {
  cmd->add_option("--out", o.out_dir, "Output directory; re-running with it resumes")->required();
  cmd->add_option("--cache-dir", o.cache_dir, "Tables and reference cache (default OUT/cache)");
  cmd->add_option("--reference-spp", o.reference_spp, "Reference rays per pixel, or auto")->capture_default_str();
  cmd->add_option("--frames", o.frames, "Interleaved frames per setting (median reported)")->capture_default_str();
  cmd->add_option("--history-frames", o.history_frames, "Sequence length of a setting with the image history")
      ->capture_default_str();
  render_view::add_renamed_option(cmd, "--taa-frames", "--history-frames");
  cmd->add_option("--threads", o.threads, "Threads (0 = all cores)")
      ->check(CLI::Range(0, int(foveation::kMaxExecutorThreads)))
      ->capture_default_str();
  cmd->add_flag("--quick", o.quick, "The small grid and a 320x360 motion (docs/lab/pricelist.md)");
  cmd->add_option("--heatmap", o.heatmap, "Setting id for the error heat map (default: the thesis default)");
  cmd->add_option("--md", o.md_file, "Also write the report (command, machine, tables) to this markdown file");
  cmd->add_flag("--images", o.images, "Write every setting's image (PFM, display values, and PNG)");
  cmd->add_option("--seed", o.seed, "Seed of point set and jitter")->capture_default_str();
  cmd->add_option("--white-cd-m2", o.white_cd_m2,
                  "Luminance of display white for the perceptual columns (cd/m^2)")->capture_default_str();
  render_view::add_pixel_filter_option(cmd, &o.pixel_filter);
}

// The grid's lists (kGridListOptions).
void add_grid_options(CLI::App* cmd, PricelistTexts& t) {
  const char* help[] = {"Full-render baseline rays per pixel, e.g. 1,2,4,8,16",
                        "interpolation:k list, e.g. nearest:1,msm:5,rbf:10", "Density scales, e.g. 1,1.5,2",
                        "Rays per point, e.g. 1,2,4,8", "Fovea patterns, e.g. pixel-grid,thesis",
                        "Rays per point measured with the image history too, or none",
                        "Content contrasts of the content-aware rows, e.g. 0.25,0.5,1, or none",
                        "Contrasts of the rows with rays per point by content (at rays per point > 1), e.g. 0.5, "
                        "or none"};
  for (std::size_t i = 0; i < t.lists.size(); ++i) cmd->add_option(kGridListOptions[i], t.lists[i], help[i]);
  render_view::add_renamed_option(cmd, "--taa-rays-per-point", "--history-rays-per-point");
}

// The temporal columns: the motion and its window, size and reference.
void add_temporal_column_options(CLI::App* cmd, PricelistOptions& o, PricelistTexts& t) {
  cmd->add_option("--motion", o.temporal.motion,
                  "Temporal columns over this head and gaze motion: builtin, a CSV file, or none")
      ->capture_default_str();
  cmd->add_option("--temporal-size", t.temporal_size,
                  "Eye size WxH of the motion (default 320x360 with --quick, else 640x720)");
  cmd->add_option("--temporal-frames", o.temporal.frames, "Frames of the motion")->capture_default_str();
  cmd->add_option("--temporal-start-s", o.temporal.start_s, "Time of the motion's first frame (s)")
      ->capture_default_str();
  cmd->add_option("--temporal-fps", o.temporal.fps, "Frames per second of the motion")->capture_default_str();
  cmd->add_option("--temporal-reference-spp", o.temporal.reference_spp,
                  "Rays per pixel of every reference frame of the motion")
      ->capture_default_str();
}

glm::ivec2 size_option(const char* option, const std::string& text) {
  glm::ivec2 size;
  if (std::string e; !render_view::parse_size(text, &size, &e)) throw CLI::ValidationError(option, e);
  return size;
}

// The view's texts into *o; throws CLI::ValidationError naming a bad one.
void parse_view_texts(const PricelistTexts& t, PricelistOptions* o) {
  if (!t.viewer.empty()) o->viewer_m = render_view::parse_point_option("--pose", t.viewer);
  if (!t.look_at.empty()) o->look_at_m = render_view::parse_point_option("--look-at", t.look_at);
  if (!t.gaze.empty()) o->gaze_px = render_view::parse_gaze_option("--gaze", t.gaze);
  if (!t.size.empty()) o->size_px = size_option("--size", t.size);
  if (!t.temporal_size.empty()) o->temporal.size_px = size_option("--temporal-size", t.temporal_size);
}

// The grid's lists into o->grid; throws CLI::ValidationError naming a bad one.
void parse_grid_lists(const PricelistTexts& t, PricelistOptions* o) {
  for (std::size_t i = 0; i < t.lists.size(); ++i) {
    const std::string& text = t.lists[i];
    if (text.empty()) continue;
    if (o->quick) throw CLI::ValidationError(kGridListOptions[i], "give --quick or a grid list, not both");
    std::string bad;
    if (i == 0) bad = parse_numbers(text, &o->grid.full_rays_per_point);
    if (i == 1 && !split_list(text, &o->grid.interpolation)) bad = "expected a comma-separated list";
    if (i == 2) bad = parse_numbers(text, &o->grid.density_scale);
    if (i == 3) bad = parse_numbers(text, &o->grid.rays_per_point);
    if (i == 4 && !split_list(text, &o->grid.pattern)) bad = "expected a comma-separated list";
    if (i == 5)
      bad = text == "none" ? (o->grid.history_rays_per_point.clear(), std::string())
                           : parse_numbers(text, &o->grid.history_rays_per_point);
    if (i == 6) bad = list_or_none(text, &o->grid.content_contrast);
    if (i == 7) bad = list_or_none(text, &o->grid.content_rays);
    if (!bad.empty()) throw CLI::ValidationError(kGridListOptions[i], bad);
  }
}

}  // namespace

void register_pricelist(CLI::App& app) {
  auto o = std::make_shared<PricelistOptions>();
  auto texts = std::make_shared<PricelistTexts>();
  CLI::App* cmd = app.add_subcommand(
      "pricelist", "What each setting costs in time and rays and buys in accuracy per eccentricity ring");
  add_view_options(cmd, *o, *texts);
  add_run_options(cmd, *o);
  add_grid_options(cmd, *texts);
  add_temporal_column_options(cmd, *o, *texts);
  cmd->callback([o, texts] {
    parse_view_texts(*texts, o.get());
    parse_grid_lists(*texts, o.get());
    const int code = run_pricelist(*o, std::cout, std::cerr);
    if (code != 0) throw CLI::RuntimeError(code);
  });
}

}  // namespace foveart::eval
