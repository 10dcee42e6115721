// The options of a render and the view they describe, shared by the product's
// `fovea render` (one still view, its speed) and the lab's commands
// (`fovea-eval accuracy`, `motion`, `pricelist`): the preset, eye, size or exact
// view, the foveated display and its tables, and the product's temporal mode.
// What only the lab asks for (a converged reference, a scripted motion, its
// temporal variants) is the lab's own (eval/lab_options.hpp).
#pragma once


#include <glm/vec2.hpp>
#include <glm/ext/vector_int2.hpp>

#include <render_view/display_options.hpp>

#include <engine/scene.hpp>
#include <engine/tracer.hpp>

#include <foveation/display_model.hpp>
#include <foveation/display_transform.hpp>
#include <foveation/executor.hpp>
#include <foveation/foveated_view.hpp>
#include <foveation/ray_samples.hpp>
#include <foveation/ray_trace.h>
#include <foveation/temporal_mode.hpp>

#include <array>
#include <cstdint>
#include <filesystem>
#include <iosfwd>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace foveart::render_view {

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
  // Content-aware density (foveation/content_density.hpp): the Michelson contrast at which
  // a screen tile traces all its points; 0: off.
  double content_contrast = 0.0;
  // Rays per point by the content (foveation/point_rays.hpp, point_ray_count): the contrast
  // from which a point casts all rays_per_point rays; 0: off (the lab's default, so that its
  // rows are what they name). Unset (`fovea render`'s default): content_rays_of.
  std::optional<double> content_rays = 0.0;
  // The eccentricity over which content_rays doubles, in steps (foveation::ContentDensityOptions::
  // rays_doubling_ecc_deg); 0: off (the lab's default). Unset (`fovea render`'s default):
  // content_rays_doubling_of.
  std::optional<double> content_rays_doubling_deg = 0.0;
  std::string pattern;            // pixel-grid | thesis; empty: the preset's
  int threads = 0;                // 0: all cores
  int frames = 3;                 // per mode, interleaved; the report gives the median frame
  // The index of the first foveated frame, the next ones counting up: with a history
  // each frame's jitter seed is seed + its index. 1: as the layer numbers its
  // frames, so that frame i of `--temporal image|rays` is the layer's frame i.
  uint64_t first_frame = 1;
  std::optional<glm::ivec2> size_px;  // --size WxH: override the preset's per-eye size (same FOV)
  // --fov-deg: another field of view than the preset's, the horizontal span of
  // a symmetric frustum or an exact OpenXR view's XrFovf angles (the point set
  // follows the horizontal span, as the layer's DisplayModel::from_fov does);
  // --pose: the eye pose in scene space (px, py, pz, qx, qy, qz, qw).
  FovDeg fov;
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
  // What the foveated frames keep from earlier ones (the layer's "temporal"):
  // off, an image history or a render cache of the traced rays.
  foveation::TemporalMode temporal = foveation::TemporalMode::off;
  bool json = false;
};

// The checks every command applies to a render's options: false and *error saying what is wrong.
[[nodiscard]] bool check_render_options(const RenderOptions& options, std::string* error);
// The eye view `fovea render` renders for these options (preset, eye, size,
// --fov, --pose) of a scene. The options must have passed check_render_options.
FoveartEyeView eye_view(const RenderOptions& options, const engine::Scene& scene);
// A view's frustum in degrees, L, R, U, D (XrFovf's angles): what the reports print and
// --fov-deg L,R,U,D reads back.
std::array<double, 4> fov_deg(const FoveartEyeView& view);
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

// The foveated view's settings for these options: the product's temporal mode
// (foveation::temporal_view_settings) at rays_per_point rays and the seed, with
// the pixel filter asked for.
foveation::ViewSettings foveated_view_settings(const RenderOptions& options);
// The contrast from which a point casts all its rays: the one asked for, or where none is
// (`fovea render`), the product's default for the rays per point and density scale
// (foveation::default_rays_contrast).
double content_rays_of(const RenderOptions& options);
// The eccentricity over which that contrast doubles: the one asked for, or where none is (`fovea
// render`), the product's default for the temporal mode (foveation::default_rays_doubling_ecc_deg).
double content_rays_doubling_of(const RenderOptions& options);

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

}  // namespace foveart::render_view
