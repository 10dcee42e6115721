// The options of a render and the view they describe, shared by `fovea render`
// (one still view) and the lab's sequences (`fovea-eval motion`): the preset,
// eye, size or exact view, the foveated display and its tables.
#pragma once


#include <glm/vec2.hpp>
#include <glm/ext/vector_int2.hpp>

#include <engine/scene.hpp>
#include <engine/tracer.hpp>

#include <foveation/display_model.hpp>
#include <foveation/display_transform.hpp>
#include <foveation/executor.hpp>
#include <foveation/foveated_view.hpp>
#include <foveation/ray_samples.hpp>
#include <foveation/ray_trace.h>

#include <array>
#include <cstdint>
#include <filesystem>
#include <iosfwd>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace foveart::tools {

struct RenderOptions {
  std::string scene = "default";
  std::string preset = "fove";
  std::string eye = "left";
  std::string mode = "full";      // full | foveated | both
  // `fovea render --engine`: who answers the rays, "cpu" (engine::Tracer) or "gpu"
  // (gpu_engine::CallbackAdapter: the GPU sample engine behind the same callback,
  // a device round trip per batch). The lab's commands trace on the CPU.
  std::string engine = "cpu";
  std::string interpolation = "nearest";  // nearest | msm | rbf
  std::optional<glm::vec2> gaze_px;  // default: image centre
  // `fovea render --gaze A;B;C`: the foveated frames' gazes in turn, the last
  // (gaze_px) for every frame after them. Empty: gaze_px for every frame.
  std::vector<glm::vec2> gaze_px_per_frame;
  int rays_per_point = 1;            // a full render's points are its pixels
  int k = 0;                      // 0: the default (reconstruction_k)
  double density_scale = 1.0;
  std::string pattern;            // pixel-grid | thesis; empty: the preset's
  int threads = 0;                // 0: all cores
  int frames = 3;                 // per mode, interleaved; the report gives the median frame
  // The index of the first foveated frame, the next ones counting up: with TAA
  // each frame's jitter seed is seed + its index. 1: as the layer numbers its
  // frames, so that frame i of `--temporal image|rays` is the layer's frame i.
  uint64_t first_frame = 1;
  std::optional<glm::ivec2> size_px;  // override the preset's per-eye size (same FOV)
  // An exact OpenXR view instead of the preset's: XrFovf angles in degrees
  // (left, right, up, down; the point set follows the horizontal span, as the
  // layer's DisplayModel::from_fov does) and the eye pose in scene space
  // (px, py, pz, qx, qy, qz, qw).
  std::optional<std::array<double, 4>> fov_deg;
  std::optional<std::array<double, 7>> pose;
  // A standing viewer instead (engine::standing_viewer): the head at viewer_m
  // (--pose X,Y,Z; default the scene's camera, or one framing the scene) facing
  // look_at_m (--look-at X,Y,Z; default the camera's direction). Metres, scene space.
  std::optional<std::array<double, 3>> viewer_m;
  std::optional<std::array<double, 3>> look_at_m;
  // How radiance becomes the PNGs' display values (foveation/display_transform.hpp):
  // "auto" (engine::auto_exposure on the view) or a linear scale > 0, and the curve.
  std::string exposure = "auto";
  std::string tone_map = "pbr-neutral";
  std::string out_prefix;         // empty: no images written
  std::string cache_dir;          // point set / neighbour table cache, empty: none
  uint64_t seed = 1;
  // Effects the engine leaves out of the scene (engine::parse_effects names,
  // e.g. "reflection,refraction"), for every image of the run, the
  // reference's too: to see what an effect costs, or what it does to a
  // measure. Empty: every effect the scene calls for.
  std::string without;
  // What every ray of a pixel follows (foveation/ray_samples.hpp): the full
  // render's, the pixel-grid fovea's and the reference's.
  foveation::PixelFilter pixel_filter = foveation::PixelFilter::box;
  // Errors against a converged reference (eval/reference.hpp): "" none, "auto" (the
  // convergence check picks the count) or an even count of rays per pixel;
  // or a linear-RGB PFM of the view's size (--reference FILE).
  std::string reference_spp;
  std::string reference_file;
  std::string reference_cache;    // reference cache directory; empty: <cache>/reference, or none
  // TAA of the foveated frames: off, restart (the history restarts on every
  // pose change) or reproject (it follows the head); with --motion a list
  // (off,restart,reproject), each rendered as its own view at equal rays.
  std::string taa = "off";
  bool taa_mean_while_young = false;  // TemporalOptions::mean_while_young (--taa-mean-while-young)
  // A scripted head and gaze motion ("builtin" or a CSV file): --frames frames
  // at start_s + i / fps, measured per ring against the reference sequence
  // (`fovea-eval motion`, eval/src/cmd_motion.cpp); `fovea render` refuses them.
  std::string motion;
  std::optional<double> start_s;  // default 0
  std::optional<double> fps;      // default 70
  bool json = false;
};

// The checks `fovea render` applies to its options: false and *error saying what is wrong.
[[nodiscard]] bool check_render_options(const RenderOptions& options, std::string* error);
// The eye view `fovea render` renders for these options (preset, eye, size,
// --fov, --pose) of a scene. The options must have passed check_render_options.
FoveartEyeView render_view(const RenderOptions& options, const engine::Scene& scene);
// The display the foveated view's tables are built for (preset, size, scale,
// pattern); nullopt with *error when it is not valid.
std::optional<foveation::DisplayModel> foveated_display(const RenderOptions& options, const FoveartEyeView& view,
                                                        std::string* error);

// The engine's options for these options (the effects --without leaves out).
// The options must have passed check_render_options.
engine::TracerOptions render_tracer_options(const RenderOptions& options);

// The display transform of --exposure and --tone-map for this view; "auto" meters
// the view through the tracer (engine::auto_exposure). nullopt with *error when the
// pre-pass fails. The options must have passed check_render_options.
std::optional<foveation::DisplayTransform> render_display(const RenderOptions& options, engine::Tracer& tracer,
                                                          const FoveartEyeView& view, foveation::Executor& executor,
                                                          std::string* error);
// The same, metering "auto" through any engine's callback (`fovea render --engine gpu`).
std::optional<foveation::DisplayTransform> render_display(const RenderOptions& options, FoveartTraceRaysFn trace,
                                                          void* user_data, const FoveartEyeView& view,
                                                          foveation::Executor& executor, std::string* error);

// Neighbours the reconstruction blends: 1 for nn, else --k (default 5).
int reconstruction_k(const RenderOptions& options);

// The foveated view's tables for these options: the display of
// foveated_display, options.seed, options.method with reconstruction_k
// neighbours, read from or built into cache_dir (nullopt: built
// and not kept); `log` gets the cache's messages. nullptr with *error when the
// display is not valid or the tables cannot be built ("tables: ...").
std::shared_ptr<const foveation::ViewTables> load_foveated_tables(
    const RenderOptions& options, const FoveartEyeView& view, const std::optional<std::filesystem::path>& cache_dir,
    foveation::Executor& executor, const foveation::LogFn& log, std::string* error);

}  // namespace foveart::tools
