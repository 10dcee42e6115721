// The price list's temporal pass (pricelist_temporal.hpp).
#include <eval/pricelist_temporal.hpp>

#include <render_view/render_options.hpp>
#include <eval/taa_modes.hpp>
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

constexpr const char* kTaaModes[] = {"off", "restart", "reproject", "cache"};

// One group of the temporal pass: a TAA setting of the grid without its TAA.
struct TemporalGroup {
  PriceSetting setting;  // taa = false
};

std::string track_id(const PriceSetting& s, const std::string& mode) { return s.id() + "_taa-" + mode; }

std::vector<TemporalGroup> temporal_groups(const std::vector<PriceSetting>& settings) {
  std::vector<TemporalGroup> groups;
  for (const PriceSetting& s : settings) {
    if (s.full || !s.taa) continue;
    TemporalGroup g;
    g.setting = s;
    g.setting.taa = false;
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

std::optional<Json> run_pricelist_temporal(const TemporalContext& c, const std::vector<PriceSetting>& settings,
                                           engine::Tracer& tracer, std::uint64_t scene_hash,
                                           foveation::Executor& executor, std::ostream& err) {
  const TemporalOptions& o = c.options;
  std::string error;
  const std::optional<motion::ScriptedMotion> motion = load_motion(o.motion, &error);
  if (!motion) {  // checked before the run; the file may have gone since
    err << "fovea-eval pricelist: " << error << "\n";
    return std::nullopt;
  }
  render_view::RenderOptions view_options;
  view_options.scene = c.scene;
  view_options.preset = c.preset;
  view_options.eye = c.eye;
  view_options.size_px = temporal_size(o, c.quick);
  view_options.seed = c.seed;
  const FoveartEyeView eye_at_rest = render_view::eye_view(view_options, tracer.scene());
  const engine::Camera head = engine::scene_head(tracer.scene());
  MotionWindow window;
  window.start_s = o.start_s;
  window.fps = o.fps;
  window.frames = o.frames;
  const std::vector<MotionFrame> frames =
      motion_frames(*motion, window, eye_at_rest, foveation::EyePose{head.position_m, head.orientation});

  const fs::path results_file = c.out_dir / "temporal.jsonl";
  std::map<std::string, Json> done = read_results_jsonl(results_file, err);
  std::ofstream results(results_file, std::ios::app);
  if (!results) {
    err << "fovea-eval pricelist: cannot write " << results_file.string() << "\n";
    return std::nullopt;
  }
  const std::vector<TemporalGroup> groups = temporal_groups(settings);
  std::vector<const TemporalGroup*> todo;
  for (const TemporalGroup& g : groups) {
    bool all = true;
    for (const char* mode : kTaaModes) all = all && done.count(track_id(g.setting, mode));
    if (!all) todo.push_back(&g);
  }
  if (todo.empty() && !groups.empty() && (!done.count("full_spp1") || !done.count("reference")))
    todo.push_back(&groups.front());  // the full render or the reference is missing: measure them with one group
  if (groups.empty()) {
    err << "fovea-eval pricelist: no TAA setting in the grid (--taa-rays): no temporal columns\n";
  } else {
    err << "fovea-eval pricelist: temporal columns: " << groups.size() << " TAA setting(s) x off/restart/reproject/cache over "
        << o.frames << " frames of the " << o.motion << " motion at " << eye_at_rest.width_px << "x"
        << eye_at_rest.height_px << ", " << groups.size() - todo.size() << " already measured in "
        << results_file.string() << "\n";
  }
  SequenceReferenceOptions ref;
  ref.spp = std::to_string(o.reference_spp);
  ref.seed = c.seed;
  ref.pixel_filter = c.pixel_filter;
  ref.cache_dir = (fs::path(c.cache_dir) / "reference").string();
  const auto t_start = std::chrono::steady_clock::now();
  toolkit::Progress progress("temporal");
  for (std::size_t gi = 0; gi < todo.size(); ++gi) {
    const PriceSetting& s = todo[gi]->setting;
    std::vector<SequenceTrack> tracks;
    SequenceTrack full;
    full.id = "full_spp1";
    full.full = true;
    tracks.push_back(std::move(full));
    render_view::RenderOptions ro = view_options;
    ro.mode = "foveated";
    ro.interpolation = s.interpolation;
    ro.k = s.k;
    ro.density_scale = s.density_scale;
    ro.pattern = s.pattern;
    ro.rays_per_point = s.rays_per_point;
    const std::shared_ptr<const foveation::ViewTables> tables = render_view::load_foveated_tables(
        ro, eye_at_rest, fs::path(c.cache_dir), executor,
        [&](const std::string& m) { err << "fovea-eval pricelist: " << m << "\n"; }, &error);
    if (!tables) {
      err << "fovea-eval pricelist: " << s.id() << ": " << error << "\n";
      return std::nullopt;
    }
    for (const char* mode : kTaaModes) {
      SequenceTrack t;
      t.id = track_id(s, mode);
      t.taa = mode;
      t.spp = s.rays_per_point;
      t.view = make_taa_view(tables, mode, s.rays_per_point, c.seed, c.pixel_filter, /*taa_mean_while_young=*/false);
      tracks.push_back(std::move(t));
    }
    SequenceHooks hooks;
    hooks.log = [&](const std::string& m) { err << "fovea-eval pricelist: " << m << "\n"; };
    hooks.frame_done = [&](int frame, int total) {
      progress.update((double(gi) + double(frame) / double(total)) / double(todo.size()));
    };
    SequenceRun run;
    ref.controls = !done.count("reference");  // the controls go into the reference's line, written once
    if (!run_sequence(tracer, scene_hash, frames, ref, tracks, executor, hooks, &run, &error)) {
      err << "fovea-eval pricelist: temporal " << s.id() << ": " << error << "\n";
      return std::nullopt;
    }
    const double anchor_ms = median_ms(tracks.front().total_ms);
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
    for (const SequenceTrack& t : tracks) {
      if (t.full && done.count(t.id)) continue;
      Json j = sequence_track_json(t, run, anchor_ms);
      if (t.full) {
        j["setting"] = "full_spp1";
      } else {
        PriceSetting still = s;
        still.taa = t.taa != "off";
        j["setting"] = still.id();
        j["method"] = s.interpolation;
        j["k"] = s.k;
        j["scale"] = s.density_scale;
        j["pattern"] = s.pattern;
      }
      lines.push_back(j);
    }
    for (Json& j : lines) {
      results << j.dump() << "\n";
      const std::string id = j["id"].get<std::string>();
      done[id] = std::move(j);
    }
    results.flush();
    if (!results) {
      err << "fovea-eval pricelist: cannot write " << results_file.string() << "\n";
      return std::nullopt;
    }
    err << "fovea-eval pricelist: temporal [" << gi + 1 << "/" << todo.size() << "] " << s.id() << " measured (reference "
        << run.reference_frames_cached << "/" << frames.size() << " frames from the cache, "
        << std::lround(std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count()) << " s)\n";
  }
  Json out = {{"run", temporal_run_json(o, c.quick)}, {"reference", done.count("reference") ? done["reference"] : Json()},
              {"tracks", Json::array()}};
  out["run"]["eye"] = c.eye;
  if (done.count("full_spp1")) out["tracks"].push_back(done["full_spp1"]);
  for (const TemporalGroup& g : groups)
    for (const char* mode : kTaaModes)
      if (done.count(track_id(g.setting, mode))) out["tracks"].push_back(done[track_id(g.setting, mode)]);
  return out;
}

}  // namespace foveart::eval
