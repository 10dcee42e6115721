// The price list's temporal columns (docs/pricelist.md "Temporal columns"):
// every TAA setting of the grid (method, k, scale, pattern at the TAA rays)
// rendered over a scripted head and gaze motion four times at equal rays —
// TAA off, restarting on every pose change (the TAA before reprojection),
// reprojecting its history, and keeping the traced rays in a render cache
// (TaaHistory::ray_cache) — plus the full render at 1 ray per pixel, each
// measured per ring against the reference sequence (motion_sequence.hpp).
//
// The motion renders at its own eye size (a sequence costs frames x the
// reference's rays): 320x360 with --quick, 640x720 otherwise (temporal_size_px).
// Groups run one after another, each with the full render interleaved as its
// time anchor, so that only one group's views are in memory; the reference
// sequence is rendered once into the cache and read back by the others. Each
// group's tracks go to OUT/temporal.jsonl as they land; a re-run skips them.
#pragma once

#include <eval/pricelist_grid.hpp>

#include <engine/tracer.hpp>

#include <foveation/executor.hpp>
#include <foveation/ray_samples.hpp>

#include <glm/ext/vector_int2.hpp>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

namespace foveart::eval {

struct TemporalOptions {
  std::string motion = "builtin";       // "builtin", a CSV file, or "none" (no temporal columns)
  std::optional<glm::ivec2> size_px;    // default: 320x360 with --quick, 640x720 otherwise
  int frames = 36;
  double start_s = 1.3;                 // with 36 frames at 70 fps: 1.30-1.80 s, the 12 deg saccade at 1.5 s
  double fps = 70.0;
  // Rays per pixel of every reference frame: with the box filter 256 keeps its own flicker (its floor)
  // 10 dB below every track's. With bspline2 the render cache flickers less: 256 lies 3-6 dB below it,
  // 1024 8-12 dB at 320x360 (sanity.floor_10db_below says; docs/pricelist.md, "The reference's own share").
  int reference_spp = 256;
};

// The eye size the temporal pass renders at.
glm::ivec2 temporal_size(const TemporalOptions& options, bool quick);

// False and *error saying what is wrong with the options (the motion file, its
// window, the size, the reference count). Loads the motion to check it.
[[nodiscard]] bool check_temporal_options(const TemporalOptions& options, std::string* error);

// What the temporal pass measures, for run.json: a different one must not resume into the same OUT.
nlohmann::ordered_json temporal_run_json(const TemporalOptions& options, bool quick);

struct TemporalContext {
  TemporalOptions options;
  bool quick = false;
  std::string scene;                    // RenderOptions fields of the view: scene, preset, eye
  std::string preset;
  std::string eye;
  std::uint64_t seed = 1;
  foveation::PixelFilter pixel_filter = foveation::PixelFilter::box;  // the sequence's (SequenceReferenceOptions)
  std::string cache_dir;                // tables and reference/ below it
  std::filesystem::path out_dir;
};

// Runs (or resumes) the temporal pass for the TAA settings among `settings`.
// Returns {"run", "reference", "tracks": [...]} (tracks: sequence_track_json
// plus method, k, scale, pattern, setting), or nullopt with the problem on
// `err` (an engine or frame failure, an unwritable file).
std::optional<nlohmann::ordered_json> run_pricelist_temporal(const TemporalContext& context,
                                                             const std::vector<PriceSetting>& settings,
                                                             engine::Tracer& tracer, std::uint64_t scene_hash,
                                                             foveation::Executor& executor, std::ostream& err);

}  // namespace foveart::eval
