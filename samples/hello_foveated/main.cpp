// hello_foveated: the sample engine's glTF scene, ray traced by FoveaRT's
// foveated renderer through the OpenXR layer, until the runtime ends the session.
//   hello_foveated [--scene FILE.gltf] [--engine cpu|gpu] [--mode foveated|full|both]
//                  [--interpolation nearest|msm|rbf|config] [--k N]
//                  [--density-scale S] [--rays-per-point N] [--temporal off|image|rays|config]
//                  [--gaze-source none|provider|eye_gaze_interaction|config] [--gaze-provider SPEC]
//                  [--max-frames N] [--eye-size W H] [--exposure auto|config|X] [--tone-map CURVE]
//                  [--fault nan|error|throw|nothing] [--fault-from-frame N] [--json] [--app-actions]
//                  [--no-explicit-layer] [--count-work] [--texture-lod on|off]
//                  [--trace-model callback|app] [--release-fault never|twice|unknown]
// Every renderer setting not given here is left to the layer's config file
// ("config", 0 or no value: the extension header's "Defaults").
// --engine gpu: the GPU sample engine (samples/gpu_engine) on the session's own
// Vulkan device and queue traces through the layer's device trace
// (XrFoveatedDeviceTraceInfoFOVEART) wherever the layer reconstructs on the GPU;
// the CPU engine stays registered as traceRays for where it reconstructs on the
// CPU (the header's "Both" rule). The auto exposure pre-pass runs on the CPU
// engine either way.
// --texture-lod off (gpu): the GPU engine samples every texture at level 0 as the CPU engine,
// ignoring the rays' footprints (on: their ray cones pick the level; docs/engine.md).
// --trace-model app (--engine gpu): the app records the GPU engine's trace in
// its own command buffer and submits it itself, on a second queue where the
// device has one (the extension's app-recorded trace: acquire the frame's ray
// batch, wait for its raysReadyValue, trace, signal its tracedValue, release);
// callback (the default): the layer calls the device trace inside xrEndFrame.
// --json then adds "trace_model", and with app "app_trace": {batches_acquired,
// unreleased_batches, rejected_releases, mismatched_views, release_errors,
// last_release_error, second_queue, acquire_to_end_frame_ms {p50, p95, p99,
// count}: how much older the rays' gaze is than with the callback}.
// --release-fault (test aid, --trace-model app): never (no release), twice (a
// second release), unknown (an unknown id released instead of the batch),
// moved (the batch acquired for views 1 cm off those submitted), nan (acquired
// for views at a NaN position, which get no rays).
// --fault: test aid, the engine misbehaving on purpose to watch the layer fall
// back. cpu: nan (one NaN colour per batch), error, throw. gpu: nan (the real
// trace, then NaN over the first ray's colour), error (XR_ERROR_RUNTIME_FAILURE),
// nothing (records no commands: every colour stays unwritten). "throw" is
// CPU-only: a device trace must never throw across its C call.
// --fault-from-frame N (gpu): the device trace misbehaves from the layer's
// frame N on (the batch's frameIndex, from 1), tracing right before it.
// --mode full: the app renders every pixel of each eye itself with the chosen
// engine (--rays-per-point rays per pixel; 0: the layer config's default, 1),
// the layer's seed and jitter and no temporal history (each frame traced anew),
// through the same display transform and sRGB encode, into its own swapchain
// images, and does not opt in: the layer passes the views through
// (full_frame.hpp). "config" exposure / tone map: the config's defaults (1,
// pbr-neutral); the app reads no config file. --engine gpu: GpuTracer::record_full
// on the session's device, timed by GPU timestamps; the read back, CPU encode
// and upload after it are timed apart (transfer_encode_ms_per_eye).
// --mode both: a full session, then a foveated one, in one process.
// Note both sessions use --rays-per-point; with 0 the foveated one takes the
// config file's value, the full one the default 1.
// --json prints what report.hpp describes; without it, a short summary.
#include <algorithm>
#include <cmath>
#include <vector>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <stdexcept>
#include <iostream>
#include <map>
#include <memory>
#include <string>
#include <utility>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "engine/exposure.hpp"
#include "engine/gltf_loader.hpp"
#include "engine/render.hpp"
#include "engine/tracer.hpp"
#include "gpu_engine/gpu_tracer.hpp"
#include "foveation/display_transform.hpp"
#include "foveation/executor.hpp"
#include "full_frame.hpp"
#include "layer/sampling_defaults.hpp"
#include "report.hpp"
#include "xr_app.hpp"

namespace {

using foveart::hello::app_trace_json;
using foveart::hello::foveated_json;
using foveart::hello::full_json;
using foveart::hello::gpu_engine_json;
using foveart::hello::print_both_table;
using foveart::hello::print_foveated_summary;
using foveart::hello::print_full_summary;
using foveart::hello::ray_counts_json;
using foveart::hello::speedup_json;

// --fault: the engine misbehaving on purpose, to watch the layer's fallback.
struct FaultyEngine {
  void* tracer = nullptr;
  std::string fault;  // "nan" | "error" | "throw"
};

int32_t faulty_trace_rays(void* user_data, const FoveartRayBatch* batch) {
  auto* engine = static_cast<FaultyEngine*>(user_data);
  if (engine->fault == "error") return FOVEART_RESULT_ERROR_ENGINE_FAILURE;
  if (engine->fault == "throw") throw std::runtime_error("injected engine exception");
  const int32_t r = foveart_engine_trace_rays(engine->tracer, batch);
  if (batch->ray_count > 0) batch->out_rgb[0] = std::nanf("");
  return r;
}

// --fault with --engine gpu: the device trace misbehaving on purpose. Never throws.
struct FaultyDeviceEngine {
  foveart::gpu_engine::GpuTracer* tracer = nullptr;
  std::string fault;  // "nan" | "error" | "nothing"
  uint64_t from_frame = 0;  // the first frameIndex that faults
};

XrResult faulty_trace_rays_device(void* user_data, const XrFoveatedDeviceRayBatchFOVEART* batch) noexcept {
  auto* engine = static_cast<FaultyDeviceEngine*>(user_data);
  if (engine == nullptr || batch == nullptr) return XR_ERROR_VALIDATION_FAILURE;
  if (batch->frameIndex < engine->from_frame) return foveart_gpu_engine_trace_rays_device(engine->tracer, batch);
  if (engine->fault == "error") return XR_ERROR_RUNTIME_FAILURE;
  if (engine->fault == "nothing") return XR_SUCCESS;  // the layer's NaN fill stays: every ray unwritten
  const XrResult r = foveart_gpu_engine_trace_rays_device(engine->tracer, batch);
  if (XR_FAILED(r)) return r;
  // "nan": after the engine's compute writes, NaN bits over the first ray's colour (16 bytes).
  const VkDeviceSize bytes = 16;
  if (batch->colors.size < bytes) return r;
  VkBufferMemoryBarrier barrier{};
  barrier.sType = VK_STRUCTURE_TYPE_BUFFER_MEMORY_BARRIER;
  barrier.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT;
  barrier.dstAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
  barrier.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  barrier.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  barrier.buffer = batch->colors.buffer;
  barrier.offset = batch->colors.offset;
  barrier.size = bytes;
  vkCmdPipelineBarrier(batch->commandBuffer, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0,
                       0, nullptr, 1, &barrier, 0, nullptr);
  vkCmdFillBuffer(batch->commandBuffer, batch->colors.buffer, batch->colors.offset, bytes, 0x7FC00000u);
  return r;
}

// ---- The command line ----

struct Args {
  std::string scene_spec = "default";
  std::string engine_name = "cpu";
  std::string mode = "foveated";
  std::string interpolation = "config";
  std::string temporal = "config";
  std::string gaze_source = "config";
  std::vector<uint32_t> eye_size;
  bool no_explicit_layer = false;
  bool json = false;
  std::string exposure = "auto";
  std::string tone_map = "config";
  std::string fault;
  bool count_work = false;
  std::string texture_lod = "on";
  uint64_t fault_from_frame = 0;
  std::string trace_model = "callback";
  foveart::hello::AppOptions options;  // the settings given as they are

  bool gpu_engine() const { return engine_name == "gpu"; }
  bool run_full() const { return mode != "foveated"; }
  bool run_foveated() const { return mode != "full"; }
};

void add_scene_options(CLI::App& cli, Args& a) {
  cli.add_option("--scene", a.scene_spec, "glTF 2.0 file, or 'default' for the built-in scene");
  cli.add_option("--engine", a.engine_name,
                 "who traces: cpu (the Embree sample engine, a host callback) or gpu (the GPU sample engine on the "
                 "session's Vulkan device, through the layer's device trace; the CPU engine stays the callback for "
                 "CPU reconstruction)")
      ->check(CLI::IsMember({"cpu", "gpu"}))
      ->capture_default_str();
  cli.add_option("--mode", a.mode,
                 "foveated: the layer ray traces the views (the opt-in); full: the app renders every pixel of "
                 "each eye itself with the same engine, --rays-per-point rays per pixel (0: the layer config's "
                 "default, 1), the same display transform and sRGB encode (exposure/tone map \"config\": 1, "
                 "pbr-neutral), no temporal history, and does not opt in (--engine gpu: GPU timestamps time the "
                 "trace; its read back, CPU encode and upload are timed apart); both: a full session, then a "
                 "foveated one, and their median frame and trace times and speedup")
      ->check(CLI::IsMember({"foveated", "full", "both"}))
      ->capture_default_str();
}

void add_renderer_options(CLI::App& cli, Args& a) {
  foveart::hello::AppOptions& o = a.options;
  cli.add_option("--interpolation", a.interpolation, "nearest, msm or rbf (config = the layer config's)")
      ->check(CLI::IsMember({"nearest", "msm", "rbf", "config"}))
      ->capture_default_str();
  cli.add_option("--k", o.k, "neighbours per pixel (0 = layer config)")->check(CLI::Range(0, 20));
  cli.add_option("--density-scale", o.density_scale, "density scale (0 = layer config)")->check(CLI::Range(0.0, 16.0));
  cli.add_option("--rays-per-point", o.rays_per_point,
                 "rays per point, and per pixel of --mode full (0 = layer config; --mode full: its default, 1)")
      ->check(CLI::Range(0, 64));
  cli.add_option("--temporal", a.temporal,
                 "what a foveated frame keeps from earlier frames (config = the layer config's); a full render "
                 "keeps nothing: --mode full takes only off or config")
      ->check(CLI::IsMember({"off", "image", "rays", "config"}))
      ->capture_default_str();
  cli.add_option("--gaze-source", a.gaze_source, "where gaze comes from (config = the layer config's)")
      ->check(CLI::IsMember({"none", "provider", "eye_gaze_interaction", "config"}))
      ->capture_default_str();
  cli.add_option("--gaze-provider", o.gaze_provider, "gaze provider spec: sim, replay:FILE, ...");
  cli.add_option("--max-frames", o.max_frames, "stop after N frames (0 = until the runtime ends)");
  cli.add_option("--eye-size", a.eye_size, "per-eye image W H (default: the runtime's recommended size)")->expected(2);
}

void add_app_options(CLI::App& cli, Args& a) {
  cli.add_flag("--no-explicit-layer", a.no_explicit_layer,
               "do not name the layer (it is enabled implicitly or by XR_ENABLE_API_LAYERS)");
  cli.add_flag("--json", a.json,
               "print the layer's stats as JSON (--mode full: the full render's; both: both and the speedup)");
  cli.add_flag("--app-actions", a.options.app_actions,
               "test aid: the app enables XR_EXT_eye_gaze_interaction and uses its own gaze action too");
  cli.add_option("--exposure", a.exposure,
                 "linear exposure the app chains into each frame: auto (a low-resolution pre-pass of the start "
                 "view), config (the layer config's) or a number in (0, 1e6]")
      ->capture_default_str();
  cli.add_option("--tone-map", a.tone_map, "tone-mapping curve (config = the layer config's)")
      ->check(CLI::IsMember({"none", "pbr-neutral", "aces", "config"}))
      ->capture_default_str();
  cli.add_option("--fault", a.fault,
                 "test aid: make the engine misbehave. nan: a NaN colour; error: an error result; throw: an "
                 "exception (--engine cpu only); nothing: the device trace records nothing (--engine gpu only)")
      ->check(CLI::IsMember({"nan", "error", "throw", "nothing"}));
  cli.add_flag("--count-work", a.count_work,
               "benchmark aid, --engine gpu: the GPU engine counts the BVH nodes and triangles its traversal "
               "visits (gpu_engine.work in the JSON; the compute backend only; slows the trace)");
  cli.add_option("--texture-lod", a.texture_lod,
                 "--engine gpu: on, the rays' footprints pick the texture level; off, level 0 as the CPU engine")
      ->check(CLI::IsMember({"on", "off"}))
      ->capture_default_str();
  cli.add_option("--fault-from-frame", a.fault_from_frame,
                 "with --fault and --engine gpu: the device trace misbehaves from the layer's frame N on (from 1)");
  cli.add_option("--trace-model", a.trace_model,
                 "--engine gpu: callback (the layer records the device trace in xrEndFrame) or app (the app records "
                 "it in its own command buffer and submits it: the app-recorded trace)")
      ->check(CLI::IsMember({"callback", "app"}))
      ->capture_default_str();
  cli.add_option("--release-fault", a.options.release_fault,
                 "test aid, --trace-model app: never (the batch is never released), twice (released twice), "
                 "unknown (an unknown id released instead), moved (acquired for views 1 cm off those submitted), "
                 "nan (acquired for views at a NaN position)")
      ->check(CLI::IsMember({"never", "twice", "unknown", "moved", "nan"}));
}

// Why the options do not go together; "" when they do.
std::string conflicting_options(const Args& a) {
  if (!a.fault.empty() && a.run_full()) return "--fault is for --mode foveated only (it tests the layer's fallback)";
  if (a.mode == "full" && a.temporal != "off" && a.temporal != "config")
    return "--temporal " + a.temporal + " needs --mode foveated or both: the full render keeps no temporal history";
  if (a.fault == "throw" && a.gpu_engine())
    return "--fault throw is for --engine cpu only (a device trace must never throw)";
  if (a.fault == "nothing" && !a.gpu_engine()) return "--fault nothing is for --engine gpu only";
  if (a.count_work && !a.gpu_engine()) return "--count-work is for --engine gpu only";
  if (a.texture_lod == "off" && !a.gpu_engine()) return "--texture-lod is for --engine gpu only";
  if (a.fault_from_frame != 0 && (a.fault.empty() || !a.gpu_engine()))
    return "--fault-from-frame is for --fault with --engine gpu only";
  if (a.trace_model == "app" && (!a.gpu_engine() || a.mode != "foveated"))
    return "--trace-model app is for --engine gpu --mode foveated only";
  if (!a.options.release_fault.empty() && a.trace_model != "app") return "--release-fault is for --trace-model app only";
  return "";
}

// The named settings into a.options; false if --eye-size is not two positive numbers.
bool resolve_settings(Args& a) {
  const std::map<std::string, XrFoveatedInterpolationFOVEART> interps{
      {"nearest", XR_FOVEATED_INTERPOLATION_NEAREST_FOVEART},
      {"msm", XR_FOVEATED_INTERPOLATION_MSM_FOVEART},
      {"rbf", XR_FOVEATED_INTERPOLATION_RBF_FOVEART},
      {"config", XR_FOVEATED_INTERPOLATION_USE_CONFIG_FOVEART}};
  const std::map<std::string, XrFoveatedGazeSourceFOVEART> gazes{
      {"none", XR_FOVEATED_GAZE_SOURCE_NONE_FOVEART},
      {"provider", XR_FOVEATED_GAZE_SOURCE_PROVIDER_FOVEART},
      {"eye_gaze_interaction", XR_FOVEATED_GAZE_SOURCE_EYE_GAZE_INTERACTION_FOVEART},
      {"config", XR_FOVEATED_GAZE_SOURCE_USE_CONFIG_FOVEART}};
  const std::map<std::string, XrFoveatedTemporalFOVEART> temporals{{"off", XR_FOVEATED_TEMPORAL_OFF_FOVEART},
                                                                   {"image", XR_FOVEATED_TEMPORAL_IMAGE_FOVEART},
                                                                   {"rays", XR_FOVEATED_TEMPORAL_RAYS_FOVEART},
                                                                   {"config", XR_FOVEATED_TEMPORAL_USE_CONFIG_FOVEART}};
  const std::map<std::string, XrFoveatedToneMapFOVEART> curves{
      {"none", XR_FOVEATED_TONE_MAP_NONE_FOVEART},
      {"pbr-neutral", XR_FOVEATED_TONE_MAP_PBR_NEUTRAL_FOVEART},
      {"aces", XR_FOVEATED_TONE_MAP_ACES_FOVEART},
      {"config", XR_FOVEATED_TONE_MAP_USE_CONFIG_FOVEART}};
  foveart::hello::AppOptions& o = a.options;
  o.interpolation = interps.at(a.interpolation);
  o.gaze_source = gazes.at(a.gaze_source);
  o.temporal = temporals.at(a.temporal);
  o.tone_map = curves.at(a.tone_map);
  o.enable_layer = !a.no_explicit_layer;
  o.app_recorded_trace = a.trace_model == "app";
  if (a.eye_size.size() == 2) {
    if (a.eye_size[0] == 0 || a.eye_size[1] == 0) return false;
    o.eye_width_px = a.eye_size[0];
    o.eye_height_px = a.eye_size[1];
  }
  return true;
}

// ---- The sessions ----

// --exposure into options.exposure: auto meters the start view through the CPU engine.
bool set_exposure(const std::string& exposure, foveart::engine::Tracer& tracer, const foveart::engine::Camera& camera,
                  foveart::hello::AppOptions& options, std::string* error) {
  if (exposure == "auto") {
    foveart::foveation::Executor executor(1);  // a one-off pre-pass: no threads started for it
    const std::optional<foveart::engine::AutoExposure> metered = foveart::engine::auto_exposure(
        &foveart_engine_trace_rays, &tracer, foveart::engine::fove_eye_view(0, camera), executor, error);
    if (!metered) return false;
    options.exposure = metered->exposure;
  } else if (exposure != "config") {
    const std::optional<float> e = foveart::foveation::parse_exposure(exposure);
    if (!e) {
      *error = "--exposure must be auto, config or a number in (0, 1e6], got '" + exposure + "'";
      return false;
    }
    options.exposure = *e;
  }
  return true;
}

// --engine gpu in one session: a GpuTracer on the session's device, made once
// it exists and destroyed before it; its device counters are read then (all work finished).
struct GpuSession {
  std::unique_ptr<foveart::gpu_engine::GpuTracer> tracer;
  std::optional<foveart::engine::RayCounts> counts;
  std::optional<nlohmann::json> engine;  // gpu_engine_json, read with the counts
  std::string device;                    // the session's physical device's name
  FaultyDeviceEngine faulty;
};

// The scene's engines and the settings every session shares.
class Sessions {
 public:
  explicit Sessions(const Args& args) : args_(args), options_(args.options), faulty_{nullptr, args.fault} {}
  Sessions(const Sessions&) = delete;  // options_ may point at faulty_
  Sessions& operator=(const Sessions&) = delete;

  // Loads the scene, builds the engines and meters the exposure; false and *error on failure.
  bool prepare(std::string* error) {
    auto loaded = foveart::engine::load_scene(args_.scene_spec);
    if (!loaded.ok()) return *error = loaded.error, false;
    const foveart::engine::Camera camera = foveart::engine::scene_head(*loaded.scene);
    options_.scene_from_local.position = {camera.position_m.x, camera.position_m.y, camera.position_m.z};
    options_.scene_from_local.orientation = {camera.orientation.x, camera.orientation.y, camera.orientation.z,
                                             camera.orientation.w};
    // The GPU engine traces the same scene: a copy for it, made before the CPU tracer takes the original.
    if (args_.gpu_engine()) gpu_scene_ = *loaded.scene;  // copied again for each session's device
    std::string tracer_error;
    tracer_ = foveart::engine::Tracer::create(std::move(*loaded.scene), {}, &tracer_error);
    if (tracer_ == nullptr) return *error = "cannot build the ray tracer: " + tracer_error, false;
    options_.trace_rays = &foveart_engine_trace_rays;
    options_.user_data = tracer_.get();
    if (!set_exposure(args_.exposure, *tracer_, camera, options_, error)) return false;
    faulty_.tracer = tracer_.get();
    if (!args_.fault.empty() && !args_.gpu_engine()) {
      options_.trace_rays = &faulty_trace_rays;
      options_.user_data = &faulty_;
    }
    full_spp_ = options_.rays_per_point != 0 ? options_.rays_per_point : foveart::layer::kDefaultRaysPerPoint;
    display_ = foveart::hello::display_for(options_.exposure, options_.tone_map);
    if (args_.run_full()) full_executor_.emplace();  // the full render's threads, started once
    return true;
  }

  uint32_t full_spp() const { return full_spp_; }

  // One session, the full render or the foveated one; its JSON, or the error in *error.
  std::optional<nlohmann::json> run(bool full, std::string* error) {
    foveart::hello::AppOptions session = options_;
    tracer_->reset_counts();  // engine_rays: the session's rays, not the exposure pre-pass's
    GpuSession gpu{nullptr, std::nullopt, std::nullopt, "",
                   FaultyDeviceEngine{nullptr, args_.fault, args_.fault_from_frame}};
    if (args_.gpu_engine()) add_gpu_engine(session, full, gpu);
    foveart::hello::FullFrameTimes full_times;
    if (full) add_full_renderer(session, gpu, full_times);
    const auto result = foveart::hello::run_app(session);
    if (!result.ok) {
      *error = result.error;
      return std::nullopt;
    }
    nlohmann::json engine_rays = {{"cpu", ray_counts_json(tracer_->counts())},
                                  {"gpu", gpu.counts ? ray_counts_json(*gpu.counts) : nlohmann::json(nullptr)}};
    nlohmann::json out =
        full ? full_json(result, full_times, full_spp_, display_, args_.gpu_engine()) : foveated_json(result);
    out["mode"] = full ? "full" : "foveated";
    out["engine"] = args_.engine_name;
    out["engine_rays"] = std::move(engine_rays);
    out["gpu_engine"] = gpu.engine ? *gpu.engine : nlohmann::json(nullptr);
    out["trace_model"] = args_.trace_model;
    if (session.app_recorded_trace) out["app_trace"] = app_trace_json(result);
    return out;
  }

 private:
  // The GPU engine on the session's device: the layer's device trace (none for the full render).
  void add_gpu_engine(foveart::hello::AppOptions& session, bool full, GpuSession& gpu) {
    session.make_device_trace = [this, full, &gpu](const foveart::hello::VulkanDevice& device) {
      std::string gpu_error;
      foveart::gpu_engine::GpuTracerOptions gpu_options;
      gpu_options.count_work = args_.count_work;
      gpu_options.texture_lod = args_.texture_lod == "on";
      VkPhysicalDeviceProperties properties{};
      vkGetPhysicalDeviceProperties(device.physical_device, &properties);
      gpu.device = properties.deviceName;
      foveart::gpu_engine::GpuContext context{device.physical_device, device.device, device.queue_family_index,
                                              device.queue};
      context.ray_tracing_enabled = device.ray_tracing;
      context.trace_rays_indirect = device.trace_rays_indirect;
      gpu.tracer = foveart::gpu_engine::GpuTracer::create(context, foveart::engine::Scene(*gpu_scene_), gpu_options,
                                                          &gpu_error);
      if (gpu.tracer == nullptr) throw std::runtime_error("cannot build the GPU ray tracer: " + gpu_error);
      gpu.tracer->reset_counts();
      gpu.faulty.tracer = gpu.tracer.get();
      if (full) return foveart::hello::DeviceTrace{};  // the app traces; the layer gets none
      if (!args_.fault.empty()) return foveart::hello::DeviceTrace{&faulty_trace_rays_device, &gpu.faulty};
      return foveart::hello::DeviceTrace{&foveart_gpu_engine_trace_rays_device, gpu.tracer.get()};
    };
    session.release_device_trace = [&gpu]() noexcept {
      if (gpu.tracer == nullptr) return;
      gpu.counts = gpu.tracer->counts();
      try {
        gpu.engine = gpu_engine_json(*gpu.tracer, gpu.device);
      } catch (...) {  // noexcept: the JSON stays null rather than end the program
      }
      gpu.tracer.reset();
    };
  }

  // --mode full: the app renders every view itself with the chosen engine.
  void add_full_renderer(foveart::hello::AppOptions& session, GpuSession& gpu, foveart::hello::FullFrameTimes& times) {
    session.make_view_renderer = [this, &gpu, &times](const foveart::hello::VulkanDevice& device) {
      foveart::hello::FullFrameEngine engine;
      if (args_.gpu_engine()) {
        engine.gpu = gpu.tracer.get();
      } else {
        engine.trace_rays = &foveart_engine_trace_rays;
        engine.user_data = tracer_.get();
      }
      return foveart::hello::make_full_frame(device, engine, full_spp_, display_, &*full_executor_, &times);
    };
  }

  const Args& args_;
  foveart::hello::AppOptions options_;
  std::unique_ptr<foveart::engine::Tracer> tracer_;
  std::optional<foveart::engine::Scene> gpu_scene_;
  FaultyEngine faulty_;
  uint32_t full_spp_ = 1;
  foveart::foveation::DisplayTransform display_;
  std::optional<foveart::foveation::Executor> full_executor_;
};

// ---- The results ----

// The sessions' results: JSON (--json) or a summary; --mode both with the speedup.
void print_results(const Args& a, const std::optional<nlohmann::json>& full_stats,
                   const std::optional<nlohmann::json>& foveated_stats, uint32_t full_spp) {
  if (a.mode == "both") {
    const nlohmann::json both = {{"mode", "both"},
                                 {"engine", a.engine_name},
                                 {"full", *full_stats},
                                 {"foveated", *foveated_stats},
                                 {"speedup", speedup_json(*full_stats, *foveated_stats)}};
    if (a.json)
      std::cout << both.dump(2) << "\n";
    else print_both_table(both);
  } else if (a.json) {
    std::cout << (full_stats ? *full_stats : *foveated_stats).dump(2) << "\n";
  } else if (full_stats) {
    print_full_summary(*full_stats, a.gpu_engine(), full_spp);
  } else {
    print_foveated_summary(*foveated_stats, a.gpu_engine());
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App cli{"hello_foveated: an OpenXR app ray traced by the FoveaRT layer"};
  Args args;
  add_scene_options(cli, args);
  add_renderer_options(cli, args);
  add_app_options(cli, args);
  CLI11_PARSE(cli, argc, argv);
  if (const std::string conflict = conflicting_options(args); !conflict.empty()) {
    std::cerr << "hello_foveated: " << conflict << "\n";
    return 2;
  }
  if (!resolve_settings(args)) {
    std::cerr << "hello_foveated: --eye-size needs two positive numbers\n";
    return 2;
  }
  Sessions sessions(args);
  std::string error;
  if (!sessions.prepare(&error)) {
    std::cerr << "hello_foveated: " << error << "\n";
    return 2;
  }
  std::optional<nlohmann::json> full_stats, foveated_stats;
  if (args.run_full() && !(full_stats = sessions.run(true, &error))) {
    std::cerr << "hello_foveated: full render session: " << error << "\n";
    return 1;
  }
  if (args.run_foveated() && !(foveated_stats = sessions.run(false, &error))) {
    std::cerr << "hello_foveated: " << error << "\n";
    return 1;
  }
  print_results(args, full_stats, foveated_stats, sessions.full_spp());
  return 0;
}
