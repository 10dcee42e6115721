// The price list's temporal pass (pricelist_temporal.hpp).
#include <eval/pricelist_temporal.hpp>

#include <render_view/render_options.hpp>
#include <eval/temporal_variants.hpp>
#include <eval/results_jsonl.hpp>
#include <eval/motion_sequence.hpp>
#include <eval/motion_views.hpp>

#include <engine/render.hpp>

#include <foveation/foveated_view.hpp>

#include <toolkit/progress.hpp>

#include <chrono>
#include <fstream>
#include <map>
#include <ostream>
#include <set>
#include <utility>

namespace foveart::eval {
namespace {

using Json = nlohmann::ordered_json;
namespace fs = std::filesystem;

// The variants every setting with history is measured with, at equal rays: off, the image history
// restarting on every pose change, the product's image history and its render cache.
constexpr TemporalVariant kVariants[] = {TemporalVariant::off, TemporalVariant::restart, TemporalVariant::image,
                                         TemporalVariant::rays};

// One group of the temporal pass: a setting of the grid with history, without it.
struct TemporalGroup {
  PriceSetting setting;  // history = false
};

std::string track_id(const PriceSetting& s, TemporalVariant variant) {
  return s.id() + "_temporal-" + temporal_variant_name(variant);
}

std::vector<TemporalGroup> temporal_groups(const std::vector<PriceSetting>& settings) {
  std::vector<TemporalGroup> groups;
  for (const PriceSetting& s : settings) {
    if (s.full || !s.history) continue;
    TemporalGroup g;
    g.setting = s;
    g.setting.history = false;
    groups.push_back(g);
  }
  return groups;
}


}  // namespace

glm::ivec2 temporal_size(const TemporalOptions& o, bool quick) {
  return o.size_px.value_or(quick ? glm::ivec2(320, 360) : glm::ivec2(640, 720));
}

namespace {

std::string temporal_options_problem(const TemporalOptions& o) {
  if (o.motion == "none") return "";
  std::string error;
  const std::optional<motion::ScriptedMotion> motion = load_motion(o.motion, &error);
  if (!motion) return error;
  MotionWindow w;
  w.start_s = o.start_s;
  w.fps = o.fps;
  w.frames = o.frames;
  if (std::string bad; !check_motion_window(*motion, w, &bad)) {
    // The window's options are --temporal-* here.
    for (const char* name : {"--frames", "--start-s", "--fps"}) {
      const std::size_t at = bad.find(name);
      if (at != std::string::npos) bad.replace(at, 2, "--temporal-");
    }
    return bad;
  }
  if (o.frames > 1000) return "--temporal-frames must be in 2..1000";
  if (o.size_px && (o.size_px->x < 8 || o.size_px->y < 8 || o.size_px->x > 16384 || o.size_px->y > 16384))
    return "--temporal-size must be between 8 and 16384 pixels per side";
  const int n = o.reference_spp;
  if (n < 2 || n > 65536 || n % 2 != 0 || (n > 16 && n % 16 != 0))
    return "--temporal-reference-spp must be 2, 4, ..., 16 or a multiple of 16 up to 65536, got " + std::to_string(n);
  return "";
}

}  // namespace

bool check_temporal_options(const TemporalOptions& o, std::string* error) {
  std::string problem = temporal_options_problem(o);
  if (problem.empty()) return true;
  *error = std::move(problem);
  return false;
}

Json temporal_run_json(const TemporalOptions& o, bool quick) {
  if (o.motion == "none") return nullptr;
  const glm::ivec2 size = temporal_size(o, quick);
  return {{"motion", o.motion}, {"width", size.x}, {"height", size.y}, {"frames", o.frames},
          {"start_s", o.start_s}, {"fps", o.fps}, {"reference_spp", o.reference_spp}};
}

namespace {

constexpr const char* kTemporalWho = "fovea-eval pricelist: ";

// The motion's frames in the scene at the temporal pass's eye size, and the view options of that eye.
struct TemporalScene {
  render_view::RenderOptions view_options;
  FoveartEyeView eye_at_rest{};
  std::vector<MotionFrame> frames;
};

[[nodiscard]] bool lay_out_motion(const TemporalContext& c, const engine::Tracer& tracer, TemporalScene* t,
                                  std::string* error) {
  const TemporalOptions& o = c.options;
  const std::optional<motion::ScriptedMotion> motion = load_motion(o.motion, error);
  if (!motion) return false;  // checked before the run; the file may have gone since
  t->view_options.scene = c.scene;
  t->view_options.preset = c.preset;
  t->view_options.eye = c.eye;
  t->view_options.size_px = temporal_size(o, c.quick);
  t->view_options.seed = c.seed;
  t->eye_at_rest = render_view::eye_view(t->view_options, tracer.scene());
  const engine::Camera head = engine::scene_head(tracer.scene());
  MotionWindow window;
  window.start_s = o.start_s;
  window.fps = o.fps;
  window.frames = o.frames;
  t->frames = motion_frames(*motion, window, t->eye_at_rest, foveation::EyePose{head.position_m, head.orientation});
  return true;
}

// The groups with a variant not yet in temporal.jsonl; with none, the first group again when the full
// render or the reference is missing (they are measured with a group).
std::vector<const TemporalGroup*> groups_to_measure(const std::vector<TemporalGroup>& groups,
                                                    const std::map<std::string, Json>& done) {
  std::vector<const TemporalGroup*> todo;
  for (const TemporalGroup& g : groups) {
    bool all = true;
    for (const TemporalVariant v : kVariants) all = all && done.count(track_id(g.setting, v));
    if (!all) todo.push_back(&g);
  }
  if (todo.empty() && !groups.empty() && (!done.count("full_spp1") || !done.count("reference")))
    todo.push_back(&groups.front());
  return todo;
}

// A group's tracks: the full render at 1 ray per pixel (its time anchor) and the setting's foveated
// view with each variant at equal rays, over one set of tables.
[[nodiscard]] bool make_group_tracks(const TemporalContext& c, const PriceSetting& s, const TemporalScene& t,
                                     foveation::Executor& executor, std::ostream& err,
                                     std::vector<SequenceTrack>* tracks, std::string* error) {
  SequenceTrack full;
  full.id = "full_spp1";
  full.full = true;
  tracks->push_back(std::move(full));
  render_view::RenderOptions ro = t.view_options;
  ro.mode = "foveated";
  ro.interpolation = s.interpolation;
  ro.k = s.k;
  ro.density_scale = s.density_scale;
  ro.pattern = s.pattern;
  ro.rays_per_point = s.rays_per_point;
  const std::shared_ptr<const foveation::ViewTables> tables = render_view::load_foveated_tables(
      ro, t.eye_at_rest, fs::path(c.cache_dir), executor,
      [&](const std::string& m) { err << kTemporalWho << m << "\n"; }, error);
  if (!tables) {
    *error = s.id() + ": " + *error;
    return false;
  }
  for (const TemporalVariant v : kVariants) {
    SequenceTrack track;
    track.id = track_id(s, v);
    track.temporal = temporal_variant_name(v);
    track.spp = s.rays_per_point;
    track.view = make_variant_view(v, tables, {s.rays_per_point, c.seed, c.pixel_filter, /*mean_while_young=*/false});
    tracks->push_back(std::move(track));
  }
  return true;
}

// A measured group's lines for temporal.jsonl: the reference (once, with the controls and the frames)
// and every track not yet there, each with the still setting it belongs to.
std::vector<Json> group_lines(const PriceSetting& s, const std::vector<SequenceTrack>& tracks, const SequenceRun& run,
                              const std::vector<MotionFrame>& frames, const std::map<std::string, Json>& done) {
  std::vector<Json> lines;
  if (!done.count("reference")) {
    Json r = sequence_reference_json(run);
    r["id"] = "reference";
    Json fl = Json::array();
    for (const MotionFrame& f : frames)
      fl.push_back({{"time_s", f.time_s}, {"gaze_px", {f.gaze_px.x, f.gaze_px.y}}, {"saccade", f.saccade},
                    {"blink", f.blink}});
    r["frames"] = fl;
    lines.push_back(r);
  }
  const double anchor_ms = median_ms(tracks.front().total_ms);
  for (const SequenceTrack& t : tracks) {
    if (t.full && done.count(t.id)) continue;
    Json j = sequence_track_json(t, run, anchor_ms);
    if (t.full) {
      j["setting"] = "full_spp1";
    } else {
      PriceSetting still = s;
      still.history = t.temporal != "off";
      j["setting"] = still.id();
      j["method"] = s.interpolation;
      j["k"] = s.k;
      j["scale"] = s.density_scale;
      j["pattern"] = s.pattern;
    }
    lines.push_back(j);
  }
  return lines;
}

Json temporal_json(const TemporalContext& c, const std::vector<TemporalGroup>& groups,
                   std::map<std::string, Json>& done) {
  Json out = {{"run", temporal_run_json(c.options, c.quick)},
              {"reference", done.count("reference") ? done["reference"] : Json()},
              {"tracks", Json::array()}};
  out["run"]["eye"] = c.eye;
  if (done.count("full_spp1")) out["tracks"].push_back(done["full_spp1"]);
  for (const TemporalGroup& g : groups)
    for (const TemporalVariant v : kVariants)
      if (done.count(track_id(g.setting, v))) out["tracks"].push_back(done[track_id(g.setting, v)]);
  return out;
}

void say_what_is_measured(const TemporalContext& c, const TemporalScene& t, std::size_t groups, std::size_t todo,
                          const fs::path& results_file, std::ostream& err) {
  if (groups == 0) {
    err << kTemporalWho << "no setting with history in the grid (--history-rays-per-point): no temporal columns\n";
    return;
  }
  err << kTemporalWho << "temporal columns: " << groups << " setting(s) with history x off/restart/image/rays over "
      << c.options.frames << " frames of the " << c.options.motion << " motion at " << t.eye_at_rest.width_px << "x"
      << t.eye_at_rest.height_px << ", " << groups - todo << " already measured in " << results_file.string() << "\n";
}

}  // namespace

std::optional<Json> run_pricelist_temporal(const TemporalContext& c, const std::vector<PriceSetting>& settings,
                                           engine::Tracer& tracer, std::uint64_t scene_hash,
                                           foveation::Executor& executor, std::ostream& err) {
  std::string error;
  TemporalScene scene;
  const fs::path results_file = c.out_dir / "temporal.jsonl";
  std::map<std::string, Json> done = read_results_jsonl(results_file, err);
  std::ofstream results(results_file, std::ios::app);
  if (!lay_out_motion(c, tracer, &scene, &error) || !results) {
    err << kTemporalWho << (results ? error : "cannot write " + results_file.string()) << "\n";
    return std::nullopt;
  }
  const std::vector<TemporalGroup> groups = temporal_groups(settings);
  const std::vector<const TemporalGroup*> todo = groups_to_measure(groups, done);
  say_what_is_measured(c, scene, groups.size(), todo.size(), results_file, err);
  SequenceReferenceOptions ref;
  ref.spp = std::to_string(c.options.reference_spp);
  ref.seed = c.seed;
  ref.pixel_filter = c.pixel_filter;
  ref.cache_dir = (fs::path(c.cache_dir) / "reference").string();
  const auto t_start = std::chrono::steady_clock::now();
  toolkit::Progress progress("temporal");
  for (std::size_t gi = 0; gi < todo.size(); ++gi) {
    const PriceSetting& s = todo[gi]->setting;
    std::vector<SequenceTrack> tracks;
    if (!make_group_tracks(c, s, scene, executor, err, &tracks, &error)) {
      err << kTemporalWho << error << "\n";
      return std::nullopt;
    }
    SequenceHooks hooks;
    hooks.log = [&](const std::string& m) { err << kTemporalWho << m << "\n"; };
    hooks.frame_done = [&](int frame, int total) {
      progress.update((double(gi) + double(frame) / double(total)) / double(todo.size()));
    };
    SequenceRun run;
    ref.controls = !done.count("reference");  // the controls go into the reference's line, written once
    if (!run_sequence(tracer, scene_hash, scene.frames, ref, tracks, executor, hooks, &run, &error)) {
      err << kTemporalWho << "temporal " << s.id() << ": " << error << "\n";
      return std::nullopt;
    }
    for (Json& j : group_lines(s, tracks, run, scene.frames, done)) {
      results << j.dump() << "\n";
      const std::string id = j["id"].get<std::string>();
      done[id] = std::move(j);
    }
    results.flush();
    if (!results) {
      err << kTemporalWho << "cannot write " << results_file.string() << "\n";
      return std::nullopt;
    }
    err << kTemporalWho << "temporal [" << gi + 1 << "/" << todo.size() << "] " << s.id() << " measured (reference "
        << run.reference_frames_cached << "/" << scene.frames.size() << " frames from the cache, "
        << std::lround(std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count()) << " s)\n";
  }
  return temporal_json(c, groups, done);
}

}  // namespace foveart::eval
