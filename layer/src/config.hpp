// The layer's configuration: where it is searched, what it holds, and how a
// bad file degrades (a warning naming the key, then the default).
//
// Search chain (first existing file wins):
//   1. $FOVEART_CONFIG
//   2. $XDG_CONFIG_HOME/foveart/config.json  ($HOME/.config when unset)
//   3. <sysconfdir>/xdg/foveart/config.json  (FOVEART_SYSTEM_CONFIG_DIR)
// FOVEART_DISABLE=1 disables the layer whatever the file says.
//
// File: a JSON object with the keys of LayerConfig at top level and an
// optional "applications" object whose members, keyed by
// XrApplicationInfo::applicationName, override the top-level keys.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "layer/sampling_defaults.hpp"
#include "log.hpp"

namespace foveart::layer {

// Every key the file may hold (top level; "applications" only there).
inline constexpr std::string_view kConfigKeys[] = {
    "enabled",       "log_level",      "log_file",         "interpolation",  "k",
    "density_scale", "rays_per_point", "temporal",         "gaze_source",    "gaze_provider",
    "threads",       "cache_dir",      "wait_for_tables",  "reconstruction", "exposure",
    "tone_map",      "gaze_clock",     "content_contrast", "content_rays",   "content_rays_doubling_deg",
    "applications"};

// Keys earlier configs held: a file that names one still loads, with a warning that says
// what replaced it. "taa" and "taa_history" are read into "temporal" when the same object
// does not name it (taa false: "off"; a ray_cache history: "rays"; else "image"), and
// "worker_threads" into "threads" likewise.
struct RemovedConfigKey {
  std::string_view key;
  std::string_view replaced_by;
};
inline constexpr RemovedConfigKey kRemovedConfigKeys[] = {
    {"taa", "\"temporal\": \"off\" | \"image\" | \"rays\""},
    {"taa_history", "\"temporal\": \"image\" (reproject) or \"rays\" (ray_cache)"},
    {"pixel_filter", "the pixel filter that \"temporal\" implies (box; bspline2 for \"rays\")"},
    {"taa_mean_while_young", "nothing: the temporal blend's own weights (it was an experiment)"},
    {"worker_threads", "\"threads\" (the same count; the tools' --threads)"},
};

struct LayerConfig {
  bool enabled = true;
  LogLevel log_level = LogLevel::Warn;
  std::string log_file;  // empty: stderr only
  // Renderer defaults: an XrFoveatedRendererCreateInfoFOVEART field that says
  // "use the config" (0, NULL or a ..._USE_CONFIG_FOVEART value; the extension
  // header's "Defaults") takes these.
  std::string interpolation = "msm";  // "nearest" | "msm" | "rbf"
  uint32_t k = 5;
  float density_scale = 1.0f;
  // Content-aware density (foveation/content_density.hpp): the Michelson contrast from which
  // a screen tile traces all its points; 0: off, density by eccentricity alone. Unset: the
  // path's default (content_contrast_for_path, renderer.hpp): on where reconstruction runs on
  // the GPU, off on the CPU path.
  std::optional<float> content_contrast;
  // Rays per point by the content (foveation/point_rays.hpp): the tile contrast from which a
  // point casts all rays_per_point rays; 0: off, every point casts them all. Unset:
  // content_rays_for (renderer.hpp), on where a point casts several rays at density scale 1 or above.
  std::optional<float> content_rays;
  // The eccentricity over which content_rays doubles, in steps (foveation::ContentDensityOptions::
  // rays_doubling_ecc_deg); 0: off, the same contrast everywhere. Unset: content_rays_doubling_for
  // (renderer.hpp), 30 degrees where the history keeps the traced rays ("rays"), else off.
  std::optional<float> content_rays_doubling_deg;
  uint32_t rays_per_point = kDefaultRaysPerPoint;
  // What a frame keeps from earlier frames (foveation/temporal_mode.hpp): "off", "image"
  // (a reprojected image history) or "rays" (a render cache of the traced rays).
  // "auto": "rays" where reconstruction runs on the GPU, "image" on the CPU path, where
  // the render cache costs more than twice the image history (docs/guide.md, "Configuration").
  std::string temporal = "auto";
  std::string gaze_source = "provider";  // "none" | "provider" | "eye_gaze_interaction"
  std::string gaze_provider = "sim";     // gaze provider spec: "sim", "replay:FILE", ...
  // The provider's clock: "steady" (the host's), or "display_time": stepped to each frame's
  // display time, for a simulated runtime's virtual clock (a replay stays in step with the frames).
  std::string gaze_clock = "steady";
  uint32_t threads = 0;                  // the renderer's executor threads; 0: hardware concurrency
  std::string cache_dir;                 // point set / neighbour table cache; empty: $XDG_CACHE_HOME/foveart
  bool wait_for_tables = false;          // block the first frame until the tables are ready
  // Where reconstruction, temporal history and encode run: "auto" (the GPU when the app's
  // device can run the shaders and is not a CPU implementation such as
  // lavapipe, else the CPU), "gpu" (the app's device whatever it is; the CPU,
  // with an error in the log, when it cannot run the shaders) or "cpu".
  std::string reconstruction = "auto";
  // How radiance becomes display values (foveation/display_transform.hpp), unless the
  // app chains XrFoveatedDisplayTransformFOVEART into a frame: a linear exposure scale
  // and the curve after it ("none" | "pbr-neutral" | "aces").
  float exposure = 1.0f;
  std::string tone_map = "pbr-neutral";
};

struct ConfigResult {
  LayerConfig config;
  std::string path;                   // file used; empty if none
  std::vector<std::string> warnings;  // each names the file and the key
};

using GetEnvFn = std::function<std::optional<std::string>(const char*)>;

// The process environment (std::getenv).
GetEnvFn process_env();

// Finds, reads and validates the config for one application.
ConfigResult load_config(std::string_view application_name, const GetEnvFn& env);

// Parses one config text (exposed for tests). origin names it in warnings.
void apply_config_text(std::string_view text, std::string_view origin, std::string_view application_name,
                       ConfigResult* inout_result);

}  // namespace foveart::layer
