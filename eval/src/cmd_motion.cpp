// `fovea-eval motion`: a sequence of frames following a scripted head and
// gaze motion (motion_views.hpp), for the full render and/or the foveated view
// with each temporal variant asked for at equal rays, measured per ring against the
// converged reference sequence (motion_sequence.hpp): flicker beyond the
// truth's own change and the error over all frames.
#include <eval/cmd_motion.hpp>

#include <render_view/render_cli.hpp>
#include <eval/temporal_variants.hpp>

#include <eval/motion_sequence.hpp>
#include <eval/pricelist_grid.hpp>
#include <eval/pricelist_report.hpp>
#include <eval/pricelist_temporal_report.hpp>
#include <metrics/comparison_json.hpp>

#include <engine/gltf_loader.hpp>
#include <engine/render.hpp>
#include <engine/tracer.hpp>

#include <foveation/foveated_view.hpp>

#include <toolkit/image_io.hpp>
#include <toolkit/progress.hpp>

#include <nlohmann/json.hpp>

#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <iostream>
#include <memory>
#include <initializer_list>
#include <limits>
#include <ostream>

namespace foveart::eval {

namespace {

using Json = nlohmann::ordered_json;

std::string fixed(const Json& j, int decimals) {
  if (!j.is_number() || !std::isfinite(j.get<double>())) return "-";
  const double v = j.get<double>();
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}

// temporal_sanity's verdict: the reference sequence's own flicker and error lie at least 10 dB below every
// track's in every ring.
bool floor_10db_below(const Json& sanity) {
  const auto it = sanity.find("floor_10db_below");
  return it != sanity.end() && *it == Json(true);
}

// "" when floor_10db_below; else what is too close and what to do. Closer, the reference's noise is a visible
// share of the steadiest tracks' flicker, and their ratios to off come out lower than they are.
std::string floor_warning(const Json& sanity) {
  if (floor_10db_below(sanity)) return "";
  double least = std::numeric_limits<double>::infinity();
  std::size_t ring = 0;
  for (const char* key : {"flicker_margin_db", "error_margin_db"})
    for (std::size_t r = 0; r < sanity[key].size(); ++r)
      if (sanity[key][r].is_number() && sanity[key][r].get<double>() < least) {
        least = sanity[key][r].get<double>();
        ring = r;
      }
  if (!std::isfinite(least)) return "";
  char buf[400];
  std::snprintf(buf, sizeof buf,
                "the reference's own noise lies only %.1f dB below a track's flicker or error (ring %s; 10 dB "
                "wanted): the steadiest tracks' numbers include it, so their ratios to off read low. Four times "
                "the --reference-spp lowers it by 6 dB",
                least, ring_name(ring).c_str());
  return buf;
}

// Off over each track with history in the periphery, and each one's error gain where the user looks (the goal).
void print_goals(const Json& report, std::ostream& out) {
  bool goal_header = false;
  for (const Json& t : report["tracks"]) {
    const auto goal = t.find("goal");
    if (goal == t.end()) continue;
    if (!goal_header) {
      out << "off over each track with history at 20-30 / 30-45 / >45 deg, along the motion | at fixed pixels "
             "(goal: 5x along the motion), and its PSNR gain at 0-2.5 / 2.5-5 deg (goal: no loss):\n";
      goal_header = true;
    }
    const auto met = [&](const char* key) {
      const auto flag = goal->find(key);
      return flag != goal->end() && *flag == Json(true) ? "met" : "not met";
    };
    out << t["id"].get<std::string>() << ": " << peripheral_ratios(*goal, "flicker_tracked_ratio", 2) << " ("
        << met("peripheral_tracked_flicker_5x_lower") << ") | " << peripheral_ratios(*goal, "flicker_ratio", 2) << " | "
        << central_gains_db((*goal)["psnr_minus_off_db"]) << " dB (" << met("central_error_no_worse") << ")\n";
  }
}

void print_text(const Json& report, std::ostream& out) {
  out << "motion " << report["motion"]["spec"].get<std::string>() << ": " << report["window"]["frames"]
      << " frames at " << report["window"]["fps"] << " fps from " << report["window"]["start_s"] << " s, "
      << report["width"] << "x" << report["height"] << ", " << report["effects"].get<std::string>() << "\n";
  if (!report.contains("reference")) {
    out << "no --reference-spp: no temporal error (accuracy is measured against the reference sequence only)\n";
    for (const Json& t : report["tracks"]) out << t["id"].get<std::string>() << ": " << fixed(t["ms"], 1) << " ms\n";
    return;
  }
  out << "reference " << report["reference"]["spp"] << " rays per pixel per frame\n"
      << "flicker RMS along the motion / at fixed pixels (the error's frame-to-frame change) / PSNR dB against "
         "the reference, per ring:\n";
  out << "track";
  for (const Json& r : report["reference"]["rings"])
    out << " | " << r["from_deg"].get<double>() << "-" << (r["to_deg"].is_null() ? std::string("") : r["to_deg"].dump());
  out << "\n";
  // One line per track, control and the reference floor: per ring the measures, " / " between them. A
  // measure m sits under m in a track's rings, <control>_m and m_floor in the reference's.
  struct Measure {
    const char* key;
    int decimals;
  };
  const Json& reference_rings = report["reference"]["rings"];
  const auto table = [&](std::initializer_list<Measure> measures) {
    const auto line = [&](const std::string& name, const Json& rings, const std::string& prefix, const char* suffix) {
      out << name;
      for (const Json& r : rings) {
        bool first = true;
        for (const Measure& m : measures) {
          out << (first ? " | " : " / ") << fixed(r[prefix + m.key + suffix], m.decimals);
          first = false;
        }
      }
      out << "\n";
    };
    for (const Json& t : report["tracks"]) line(t["id"].get<std::string>(), t["rings"], "", "");
    for (const SequenceControl& c : kSequenceControls) line(c.label, reference_rings, std::string(c.key) + "_", "");
    line("reference floor (its own noise)", reference_rings, "", "_floor");
  };
  table({{"flicker_tracked", 4}, {"flicker", 4}, {"psnr", 1}});
  out << "flicker weighted by what the eye resolves (flicker_csf: the change's luma, CSF-weighted by eccentricity), "
         "per ring:\n";
  table({{"flicker_csf", 4}});
  // The periphery over the frames whose image history has settled (motion_sequence.hpp).
  out << "periphery (> 20 deg) over the " << report["reference"]["settled_frames"] << " frames at least "
      << report["reference"]["settle_frames"]
      << " frames after the motion's last restart: flicker along the motion / at fixed pixels / PSNR dB\n";
  const auto settled = [&](const std::string& name, const Json& bands) {
    const Json* periphery = find_band(bands, kPeripheralBand);
    if (periphery == nullptr) return;
    const Json& s = (*periphery)["settled"];
    out << name << " | " << fixed(s["flicker_tracked"], 4) << " / " << fixed(s["flicker"], 4) << " / "
        << fixed(s["psnr"], 1) << "\n";
  };
  for (const Json& t : report["tracks"]) settled(t["id"].get<std::string>(), t["bands"]);
  for (const SequenceControl& c : kSequenceControls)
    settled(c.label, report["reference"][std::string(c.key) + "_bands"]);
  print_goals(report, out);
  if (report.contains("sanity")) {
    const Json& sanity = report["sanity"];
    out << "reference floor at least 10 dB below every track's flicker and error in every ring: "
        << (floor_10db_below(sanity) ? "yes" : "no") << "\n";
  }
}

}  // namespace

namespace {

constexpr const char* kMotionWho = "fovea-eval motion: ";

std::string options_problem(const MotionOptions& m, std::vector<TemporalVariant>* variants) {
  const render_view::RenderOptions& o = m.render;
  std::string bad;
  if (!render_view::check_render_options(o, &bad)) return bad;
  if (m.motion.empty()) return "--motion is required ('builtin' or a CSV file)";
  if (o.pose || o.viewer_m || o.look_at_m)
    return "--pose and --look-at exclude --motion: the motion gives the head pose";
  if (o.gaze_px) return "--gaze and --motion exclude each other: the motion gives the gaze";
  if (!m.reference.file.empty()) return "--reference FILE is one still image; with --motion use --reference-spp";
  if (!check_reference_choice(m.reference, &bad)) return bad;
  if (!parse_temporal_variants(m.temporal, variants, &bad)) return bad;
  if (o.mode == "full" && *variants != std::vector<TemporalVariant>{TemporalVariant::off})
    return "--temporal needs --mode foveated or both";
  return "";
}

// The scene, its tracer and the motion's frames in it.
struct MotionScene {
  std::unique_ptr<engine::Tracer> tracer;
  std::uint64_t hash = 0;
  FoveartEyeView eye_at_rest{};
  std::vector<MotionFrame> frames;
};

// Loads the scene and lays the window's frames out in it; false with *error.
[[nodiscard]] bool set_up(const MotionOptions& m, const motion::ScriptedMotion& script, const MotionWindow& window,
            std::ostream& err, MotionScene* s, std::string* error) {
  const render_view::RenderOptions& o = m.render;
  engine::LoadResult loaded = engine::load_scene(o.scene);
  if (!loaded.ok()) {
    *error = loaded.error;
    return false;
  }
  for (const std::string& w : loaded.scene->warnings) err << kMotionWho << "warning: " << w << "\n";
  s->tracer = engine::Tracer::create(std::move(*loaded.scene), render_view::render_tracer_options(o), error);
  if (!s->tracer) return false;
  s->hash = rendered_scene_hash(*s->tracer);
  s->eye_at_rest = render_view::eye_view(o, s->tracer->scene());
  const engine::Camera head = engine::scene_head(s->tracer->scene());
  s->frames = motion_frames(script, window, s->eye_at_rest, foveation::EyePose{head.position_m, head.orientation});
  return true;
}

// The full render's track (unless --mode foveated) and a foveated track per temporal variant (unless --mode full).
[[nodiscard]] bool make_tracks(const MotionOptions& m, const std::vector<TemporalVariant>& variants,
                               const MotionScene& s, foveation::Executor& executor, std::ostream& err,
                               std::vector<SequenceTrack>* tracks, std::string* error) {
  const render_view::RenderOptions& o = m.render;
  if (o.mode != "foveated") {
    SequenceTrack t;
    t.full = true;
    t.spp = o.rays_per_point;
    t.id = "full_spp" + std::to_string(o.rays_per_point);
    tracks->push_back(std::move(t));
  }
  if (o.mode == "full") return true;
  std::optional<std::filesystem::path> cache;
  if (!o.cache_dir.empty()) cache = std::filesystem::path(o.cache_dir);
  const std::shared_ptr<const foveation::ViewTables> tables = render_view::load_foveated_tables(
      o, s.eye_at_rest, cache, executor, [&](const std::string& msg) { err << kMotionWho << msg << "\n"; }, error);
  if (!tables) return false;
  PriceSetting setting;
  setting.interpolation = o.interpolation;
  setting.k = render_view::reconstruction_k(o);
  setting.density_scale = o.density_scale;
  setting.pattern = foveation::fovea_pattern_name(tables->key.display.fovea_pattern);
  setting.rays_per_point = o.rays_per_point;
  // Content density reads the colours at the display's exposure, as the product's view does.
  float exposure = 1.0f;
  if (render_view::foveated_view_settings(o).content_density.enabled()) {
    const std::optional<foveation::DisplayTransform> display =
        render_view::render_display(o, *s.tracer, s.eye_at_rest, executor, error);
    if (!display) return false;
    exposure = display->exposure;
  }
  for (const TemporalVariant variant : variants) {
    SequenceTrack t;
    t.temporal = temporal_variant_name(variant);
    t.spp = o.rays_per_point;
    t.id = setting.id() + "_temporal-" + t.temporal;
    t.view = make_variant_view(variant, tables, variant_settings(o, m.mean_while_young, exposure));
    tracks->push_back(std::move(t));
  }
  return true;
}

SequenceReferenceOptions sequence_reference(const MotionOptions& m) {
  const render_view::RenderOptions& o = m.render;
  SequenceReferenceOptions ref;
  ref.spp = m.reference.spp;  // empty: no reference, no temporal error
  ref.baseline_spp = std::max(16, o.rays_per_point);
  ref.seed = o.seed;
  ref.pixel_filter = o.pixel_filter;
  ref.mean_while_young = m.mean_while_young;
  ref.cache_dir = reference_cache_dir(m.reference, o.cache_dir);
  return ref;
}

// Progress, a line every 10 frames (or at least every 30 s: a log shows the run is alive while a
// reference sequence of many rays per pixel renders), and with --out every track's frames as PNGs.
SequenceHooks sequence_hooks(const MotionOptions& m, std::ostream& err, toolkit::Progress& progress, Json* files) {
  SequenceHooks hooks;
  hooks.log = [&err](const std::string& msg) { err << kMotionWho << msg << "\n"; };
  auto last_line = std::make_shared<std::chrono::steady_clock::time_point>(std::chrono::steady_clock::now());
  hooks.frame_done = [&err, &progress, last_line](int done, int total) {
    progress.update(double(done) / double(total));
    const auto now = std::chrono::steady_clock::now();
    if (done % 10 == 0 || done == total || now - *last_line >= std::chrono::seconds(30)) {
      err << kMotionWho << "frame " << done << "/" << total << "\n";
      *last_line = now;
    }
  };
  if (!m.render.out_prefix.empty()) {
    hooks.image = [prefix = m.render.out_prefix, files](const SequenceTrack& t, const MotionFrame& f,
                                                        const foveation::ImageRgb& display) {
      char suffix[32];
      std::snprintf(suffix, sizeof suffix, "_f%03d.png", f.index);
      const std::string path = prefix + "_" + t.id + suffix;
      if (std::string e; !toolkit::write_png(path, display, toolkit::PngValues::display, &e)) return e;
      files->push_back(path);
      return std::string();
    };
  }
  return hooks;
}

Json frames_json(const std::vector<MotionFrame>& frames, const std::vector<SequenceTrack>& tracks) {
  std::vector<std::uint8_t> temporal_reset(frames.size(), 0);  // per frame: some track's history restarted
  for (const SequenceTrack& t : tracks)
    for (int i : t.temporal_reset_frames) temporal_reset[std::size_t(i)] = 1;
  Json list = Json::array();
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const MotionFrame& f = frames[i];
    list.push_back({{"index", f.index}, {"time_s", f.time_s}, {"gaze_px", {f.gaze_px.x, f.gaze_px.y}},
                    {"saccade", f.saccade}, {"blink", f.blink}, {"gaze_off_view", f.gaze_off_view},
                    {"temporal_reset", temporal_reset[i] != 0},
                    {"pose", {f.view.position_m[0], f.view.position_m[1], f.view.position_m[2],
                              f.view.orientation_xyzw[0], f.view.orientation_xyzw[1], f.view.orientation_xyzw[2],
                              f.view.orientation_xyzw[3]}}});
  }
  return list;
}

// Every track's JSON; with a reference, issue #18's goal for each track with history against the off track
// at equal rays when both were measured (the full render's "temporal" is null, a foveated track's its variant).
Json tracks_json(const std::vector<SequenceTrack>& tracks, const SequenceRun& run, bool measured) {
  const double anchor_ms = tracks.front().full ? median_ms(tracks.front().total_ms) : 0.0;
  Json list = Json::array();
  for (const SequenceTrack& t : tracks) {
    Json j = sequence_track_json(t, run, anchor_ms);
    if (!measured) {
      j.erase("rings");
      j.erase("bands");
    }
    list.push_back(j);
  }
  if (!measured) return list;
  const auto off = std::find_if(list.begin(), list.end(), [](const Json& t) { return t["temporal"] == "off"; });
  if (off == list.end()) return list;
  const Json off_track = *off;
  for (Json& t : list)
    if (t["temporal"].is_string() && t["temporal"] != "off") t["goal"] = temporal_goal(off_track, t);
  return list;
}

Json report_json(const MotionOptions& m, const motion::ScriptedMotion& script, const MotionWindow& window,
                 const MotionScene& s, const std::vector<SequenceTrack>& tracks, const SequenceRun& run,
                 unsigned threads) {
  const bool measured = !m.reference.spp.empty();
  Json report;
  report["scene"] = s.tracer->scene().source;
  report["effects"] = engine::to_string(s.tracer->effects());
  report["eye"] = m.render.eye;
  report["width"] = s.eye_at_rest.width_px;
  report["height"] = s.eye_at_rest.height_px;
  report["threads"] = threads;
  report["pixel_filter"] = foveation::pixel_filter_name(m.render.pixel_filter);
  report["temporal_mean_while_young"] = m.mean_while_young;
  report["motion"] = {{"spec", m.motion}, {"duration_s", script.duration_s()}};
  report["window"] = {{"start_s", window.start_s}, {"fps", window.fps}, {"frames", window.frames}};
  report["frames"] = frames_json(s.frames, tracks);
  if (measured) report["reference"] = sequence_reference_json(run);
  report["tracks"] = tracks_json(tracks, run, measured);
  // The reference's own flicker and error against every track's, as the price list checks them.
  if (measured) report["sanity"] = temporal_sanity(report);
  return report;
}

}  // namespace

int run_motion(const MotionOptions& m, std::ostream& out, std::ostream& err) {
  std::vector<TemporalVariant> variants;
  std::string error;
  if (std::string bad = options_problem(m, &variants); !bad.empty()) {
    err << kMotionWho << bad << "\n";
    return 2;
  }
  const std::optional<motion::ScriptedMotion> script = load_motion(m.motion, &error);
  MotionWindow window;
  window.start_s = m.start_s.value_or(0.0);
  window.fps = m.fps.value_or(70.0);
  window.frames = m.render.frames;
  if (!script || !check_motion_window(*script, window, &error)) {
    err << kMotionWho << error << "\n";
    return 2;
  }
  MotionScene s;
  foveation::Executor executor(static_cast<unsigned>(m.render.threads));
  std::vector<SequenceTrack> tracks;
  if (!set_up(m, *script, window, err, &s, &error) || !make_tracks(m, variants, s, executor, err, &tracks, &error)) {
    err << kMotionWho << error << "\n";
    return 1;
  }
  toolkit::Progress progress("motion");
  Json files = Json::array();
  SequenceRun run;
  if (!run_sequence(*s.tracer, s.hash, s.frames, sequence_reference(m), tracks, executor,
                    sequence_hooks(m, err, progress, &files), &run, &error)) {
    err << kMotionWho << error << "\n";
    return 1;
  }
  Json report = report_json(m, *script, window, s, tracks, run, executor.thread_count());
  if (report.contains("sanity"))
    if (const std::string w = floor_warning(report["sanity"]); !w.empty()) err << kMotionWho << w << "\n";
  if (!m.render.out_prefix.empty()) report["images"] = files;
  if (m.render.json)
    out << report.dump(2) << "\n";
  else
    print_text(report, out);
  return 0;
}

void register_motion(CLI::App& app) {
  auto m = std::make_shared<MotionOptions>();
  CLI::App* cmd = app.add_subcommand(
      "motion",
      "Render a sequence over a scripted head and gaze motion, per temporal variant, against the reference sequence");
  const std::shared_ptr<render_view::RenderOptions> render(m, &m->render);
  const std::function<void()> parse_common = render_view::add_render_options(cmd, render);
  add_temporal_lab_options(cmd, &m->temporal, &m->mean_while_young, /*list=*/true);
  add_reference_options(cmd, &m->reference, /*with_file=*/false);
  cmd->add_option("--motion", m->motion,
                  "The head and gaze motion: 'builtin' or a CSV file "
                  "(time_s,qx,qy,qz,qw,px,py,pz,gx,gy,gz,valid[,saccade])")
      ->capture_default_str();
  auto start_s = std::make_shared<double>(0.0);
  auto fps = std::make_shared<double>(70.0);
  CLI::Option* start_opt = cmd->add_option("--start-s", *start_s, "Time of the first frame (s), default 0");
  CLI::Option* fps_opt = cmd->add_option("--fps", *fps, "Frames per second, default 70");
  cmd->callback([m, parse_common, start_s, fps, start_opt, fps_opt] {
    parse_common();
    if (start_opt->count() > 0) m->start_s = *start_s;
    if (fps_opt->count() > 0) m->fps = *fps;
    const int code = run_motion(*m, std::cout, std::cerr);
    if (code != 0) throw CLI::RuntimeError(code);
  });
}

}  // namespace foveart::eval
