// hello_foveated: the sample engine's glTF scene, ray traced by FoveaRT's
// foveated renderer through the OpenXR layer, until the runtime ends the session.
//   hello_foveated [--scene FILE.gltf] [--engine cpu|gpu] [--interpolation nearest|msm|rbf|config] [--k N]
//                  [--density-scale S] [--rays-per-point N] [--temporal off|image|rays|config]
//                  [--gaze-source none|provider|eye_gaze_interaction|config] [--gaze-provider SPEC]
//                  [--max-frames N] [--eye-size W H] [--exposure auto|config|X] [--tone-map CURVE]
//                  [--fault nan|error|throw|nothing] [--json] [--app-actions] [--no-explicit-layer]
// Every renderer setting not given here is left to the layer's config file
// ("config", 0 or no value: the extension header's "Defaults").
// --engine gpu: the GPU sample engine (samples/gpu_engine) on the session's own
// Vulkan device and queue traces through the layer's device trace
// (XrFoveatedDeviceTraceInfoFOVEART) wherever the layer reconstructs on the GPU;
// the CPU engine stays registered as traceRays for where it reconstructs on the
// CPU (the header's "Both" rule). The auto exposure pre-pass runs on the CPU
// engine either way.
// --fault: test aid, the engine misbehaving on purpose to watch the layer fall
// back. cpu: nan (one NaN colour per batch), error, throw. gpu: nan (the real
// trace, then NaN over the first ray's colour), error (XR_ERROR_RUNTIME_FAILURE),
// nothing (records no commands: every colour stays unwritten). "throw" is
// CPU-only: a device trace must never throw across its C call.
// --json prints, besides the layer's stats: "engine" (cpu | gpu) and "engine_rays"
// {"cpu": {primary, shadow, reflection, refraction}, "gpu": {...} or null}: the
// rays each engine traced for the layer during the session (the CPU engine's
// counts exclude the exposure pre-pass; the GPU engine's are its device counters).
// --json adds, per traced frame and in the same order: gaze_px_per_frame [frame, left x,
// left y, right x, right y], taa_reset_per_frame [left, right] (the eye's TAA history
// restarted), gaze_saccade_per_frame / gaze_blink_per_frame (the gaze provider flagged
// a saccade / a blink for it) and display_time_s_per_frame (predicted display time
// after the first traced frame's); taa_resets counts restarts of both eyes.
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
#include "xr_app.hpp"

namespace {

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
};

XrResult faulty_trace_rays_device(void* user_data, const XrFoveatedDeviceRayBatchFOVEART* batch) noexcept {
  auto* engine = static_cast<FaultyDeviceEngine*>(user_data);
  if (engine == nullptr || batch == nullptr) return XR_ERROR_VALIDATION_FAILURE;
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

nlohmann::json ray_counts_json(const foveart::engine::RayCounts& c) {
  return {{"primary", c.primary}, {"shadow", c.shadow}, {"reflection", c.reflection}, {"refraction", c.refraction}};
}

const char* gaze_source_name(XrFoveatedGazeSourceFOVEART s) {
  switch (s) {
    case XR_FOVEATED_GAZE_SOURCE_PROVIDER_FOVEART: return "provider";
    case XR_FOVEATED_GAZE_SOURCE_EYE_GAZE_INTERACTION_FOVEART: return "eye_gaze_interaction";
    default: return "none";
  }
}

// Percentile by nearest rank; 0 for no samples.
float percentile(std::vector<float> v, double p) {
  if (v.empty()) return 0.0f;
  std::sort(v.begin(), v.end());
  const auto rank = static_cast<std::size_t>(std::ceil(p / 100.0 * static_cast<double>(v.size())));
  return v[std::min(v.size() - 1, rank == 0 ? 0 : rank - 1)];
}

nlohmann::json distribution(const std::vector<float>& v) {
  return {{"p50", percentile(v, 50)}, {"p99", percentile(v, 99)}, {"count", v.size()}};
}

nlohmann::json stats_json(const foveart::hello::AppResult& r) {
  const auto& s = r.stats;
  nlohmann::json eyes = nlohmann::json::array();
  for (int e = 0; e < 2; ++e) {
    eyes.push_back({{"points", s.pointsPerEye[e]},
                    {"rays", s.raysPerEye[e]},
                    {"select_ms", s.selectMs[e]},
                    {"trace_ms", s.traceMs[e]},
                    {"interpolate_ms", s.interpolateMs[e]},
                    {"taa_ms", s.taaMs[e]},
                    {"upload_ms", s.uploadMs[e]}});
  }
  const auto& rec = r.reconstruction;
  nlohmann::json gpu_ms = nlohmann::json::array();
  for (int e = 0; e < 2; ++e) {
    gpu_ms.push_back({{"scatter", rec.gpuScatterMs[e]},
                      {"gather", rec.gpuGatherMs[e]},
                      {"taa", rec.gpuTaaMs[e]},
                      {"encode", rec.gpuEncodeMs[e]}});
  }
  const char* path = rec.path == XR_FOVEATED_RECONSTRUCTION_PATH_GPU_FOVEART   ? "gpu"
                     : rec.path == XR_FOVEATED_RECONSTRUCTION_PATH_CPU_FOVEART ? "cpu"
                                                                               : "none";
  const char* temporal = rec.temporal == XR_FOVEATED_TEMPORAL_RAYS_FOVEART    ? "rays"
                         : rec.temporal == XR_FOVEATED_TEMPORAL_IMAGE_FOVEART ? "image"
                                                                              : "off";
  // [left, right] per frame, built element by element: the std::array<bool, 2>
  // conversion trips GCC 12's false -Wnull-dereference inside nlohmann.
  nlohmann::json taa_reset = nlohmann::json::array();
  for (const auto& frame : r.taa_reset) {
    nlohmann::json pair = nlohmann::json::array();
    pair.push_back(frame[0]);
    pair.push_back(frame[1]);
    taa_reset.push_back(std::move(pair));
  }
  nlohmann::json views = nlohmann::json::array();
  for (const auto& v : r.views) {
    views.push_back({{"position_m", {v.pose.position.x, v.pose.position.y, v.pose.position.z}},
                     {"orientation_xyzw",
                      {v.pose.orientation.x, v.pose.orientation.y, v.pose.orientation.z, v.pose.orientation.w}},
                     {"fov_rad", {v.fov.angleLeft, v.fov.angleRight, v.fov.angleUp, v.fov.angleDown}},
                     {"size_px", {v.width_px, v.height_px}}});
  }
  return {{"frames_submitted", r.frames},
          {"views", views},
          {"frames_traced", s.framesTraced},
          {"views_fallback", s.framesFallback},
          {"eyes", eyes},
          {"reconstruction", path},
          {"temporal", temporal},
          {"gpu_stage_ms", gpu_ms},
          {"gpu_fallbacks", rec.gpuFallbacks},
          {"gaze_age_ms", s.gazeAgeMs},
          {"gaze_source", gaze_source_name(s.gazeSource)},
          {"fallback_flags", s.fallbackFlags},
          {"callback_failures", s.callbackFailures},
          {"invalid_colours", s.invalidColours},
          {"gaze_lost_frames", s.gazeLostFrames},
          {"gaze_px_per_frame", r.gaze_px},
          {"taa_resets", rec.taaResets},
          {"taa_reset_per_frame", taa_reset},
          {"gaze_saccade_per_frame", r.gaze_saccade},
          {"gaze_blink_per_frame", r.gaze_blink},
          {"display_time_s_per_frame", r.display_time_s},
          {"app_gaze_located_frames", r.app_gaze_located_frames},
          {"per_frame",
           {{"gaze_age_ms", distribution(r.gaze_age_ms)},
            {"layer_overhead_ms", {distribution(r.overhead_ms[0]), distribution(r.overhead_ms[1])}},
            {"trace_ms", {distribution(r.trace_ms[0]), distribution(r.trace_ms[1])}}}}};
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App cli{"hello_foveated: an OpenXR app ray traced by the FoveaRT layer"};
  std::string scene_spec = "default";
  std::string interpolation = "config";
  std::string gaze_source = "config";
  std::string temporal = "config";
  foveart::hello::AppOptions options;
  bool json = false;
  bool no_explicit_layer = false;
  std::string fault;
  std::string engine_name = "cpu";
  cli.add_option("--scene", scene_spec, "glTF 2.0 file, or 'default' for the built-in scene");
  cli.add_option("--engine", engine_name,
                 "who traces: cpu (the Embree sample engine, a host callback) or gpu (the GPU sample engine on the "
                 "session's Vulkan device, through the layer's device trace; the CPU engine stays the callback for "
                 "CPU reconstruction)")
      ->check(CLI::IsMember({"cpu", "gpu"}))
      ->capture_default_str();
  cli.add_option("--interpolation", interpolation, "nearest, msm or rbf (config = the layer config's)")
      ->check(CLI::IsMember({"nearest", "msm", "rbf", "config"}))
      ->capture_default_str();
  cli.add_option("--k", options.k, "neighbours per pixel (0 = layer config)")->check(CLI::Range(0, 20));
  cli.add_option("--density-scale", options.density_scale, "density scale (0 = layer config)")
      ->check(CLI::Range(0.0, 16.0));
  cli.add_option("--rays-per-point", options.rays_per_point, "rays per point (0 = layer config)")
      ->check(CLI::Range(0, 64));
  cli.add_option("--temporal", temporal, "what a frame keeps from earlier frames (config = the layer config's)")
      ->check(CLI::IsMember({"off", "image", "rays", "config"}))
      ->capture_default_str();
  cli.add_option("--gaze-source", gaze_source, "where gaze comes from (config = the layer config's)")
      ->check(CLI::IsMember({"none", "provider", "eye_gaze_interaction", "config"}))
      ->capture_default_str();
  cli.add_option("--gaze-provider", options.gaze_provider, "gaze provider spec: sim, replay:FILE, ...");
  cli.add_option("--max-frames", options.max_frames, "stop after N frames (0 = until the runtime ends)");
  std::vector<uint32_t> eye_size;
  cli.add_option("--eye-size", eye_size, "per-eye image W H (default: the runtime's recommended size)")
      ->expected(2);
  cli.add_flag("--no-explicit-layer", no_explicit_layer,
               "do not name the layer (it is enabled implicitly or by XR_ENABLE_API_LAYERS)");
  cli.add_flag("--json", json, "print the layer's stats as JSON");
  cli.add_flag("--app-actions", options.app_actions,
               "test aid: the app enables XR_EXT_eye_gaze_interaction and uses its own gaze action too");
  std::string exposure = "auto";
  std::string tone_map = "config";
  cli.add_option("--exposure", exposure,
                 "linear exposure the app chains into each frame: auto (a low-resolution pre-pass of the start "
                 "view), config (the layer config's) or a number > 0")
      ->capture_default_str();
  cli.add_option("--tone-map", tone_map, "tone-mapping curve (config = the layer config's)")
      ->check(CLI::IsMember({"none", "pbr-neutral", "aces", "config"}))
      ->capture_default_str();
  cli.add_option("--fault", fault,
                 "test aid: make the engine misbehave. nan: a NaN colour; error: an error result; throw: an "
                 "exception (--engine cpu only); nothing: the device trace records nothing (--engine gpu only)")
      ->check(CLI::IsMember({"nan", "error", "throw", "nothing"}));
  CLI11_PARSE(cli, argc, argv);
  const bool gpu_engine = engine_name == "gpu";
  if (fault == "throw" && gpu_engine) {
    std::cerr << "hello_foveated: --fault throw is for --engine cpu only (a device trace must never throw)\n";
    return 2;
  }
  if (fault == "nothing" && !gpu_engine) {
    std::cerr << "hello_foveated: --fault nothing is for --engine gpu only\n";
    return 2;
  }

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
  const std::map<std::string, XrFoveatedTemporalFOVEART> temporals{
      {"off", XR_FOVEATED_TEMPORAL_OFF_FOVEART},
      {"image", XR_FOVEATED_TEMPORAL_IMAGE_FOVEART},
      {"rays", XR_FOVEATED_TEMPORAL_RAYS_FOVEART},
      {"config", XR_FOVEATED_TEMPORAL_USE_CONFIG_FOVEART}};
  options.interpolation = interps.at(interpolation);
  options.gaze_source = gazes.at(gaze_source);
  options.temporal = temporals.at(temporal);
  options.enable_layer = !no_explicit_layer;
  if (eye_size.size() == 2) {
    if (eye_size[0] == 0 || eye_size[1] == 0) {
      std::cerr << "hello_foveated: --eye-size needs two positive numbers\n";
      return 2;
    }
    options.eye_width_px = eye_size[0];
    options.eye_height_px = eye_size[1];
  }

  auto loaded = foveart::engine::load_scene(scene_spec);
  if (!loaded.ok()) {
    std::cerr << "hello_foveated: " << loaded.error << "\n";
    return 2;
  }
  const foveart::engine::Camera camera = foveart::engine::scene_head(*loaded.scene);
  options.scene_from_local.position = {camera.position_m.x, camera.position_m.y, camera.position_m.z};
  options.scene_from_local.orientation = {camera.orientation.x, camera.orientation.y, camera.orientation.z,
                                          camera.orientation.w};
  std::string error;
  // The GPU engine traces the same scene: a copy for it, made before the CPU tracer takes the original.
  std::optional<foveart::engine::Scene> gpu_scene;
  if (gpu_engine) gpu_scene = *loaded.scene;
  auto tracer = foveart::engine::Tracer::create(std::move(*loaded.scene), {}, &error);
  if (tracer == nullptr) {
    std::cerr << "hello_foveated: cannot build the ray tracer: " << error << "\n";
    return 2;
  }
  options.trace_rays = &foveart_engine_trace_rays;
  options.user_data = tracer.get();
  const std::map<std::string, XrFoveatedToneMapFOVEART> curves{
      {"none", XR_FOVEATED_TONE_MAP_NONE_FOVEART},
      {"pbr-neutral", XR_FOVEATED_TONE_MAP_PBR_NEUTRAL_FOVEART},
      {"aces", XR_FOVEATED_TONE_MAP_ACES_FOVEART},
      {"config", XR_FOVEATED_TONE_MAP_USE_CONFIG_FOVEART}};
  options.tone_map = curves.at(tone_map);
  if (exposure == "auto") {
    foveart::foveation::Executor executor(1);  // a one-off pre-pass: no threads started for it
    const std::optional<foveart::engine::AutoExposure> metered = foveart::engine::auto_exposure(
        &foveart_engine_trace_rays, tracer.get(), foveart::engine::fove_eye_view(0, camera), executor, &error);
    if (!metered) {
      std::cerr << "hello_foveated: " << error << "\n";
      return 2;
    }
    options.exposure = metered->exposure;
  } else if (exposure != "config") {
    char* end = nullptr;
    options.exposure = std::strtof(exposure.c_str(), &end);
    if (end == exposure.c_str() || *end != '\0' || !std::isfinite(options.exposure) || !(options.exposure > 0.0f)) {
      std::cerr << "hello_foveated: --exposure must be auto, config or a number > 0, got '" << exposure << "'\n";
      return 2;
    }
  }
  tracer->reset_counts();  // engine_rays: the session's rays, not the exposure pre-pass's
  FaultyEngine faulty{tracer.get(), fault};
  if (!fault.empty() && !gpu_engine) {
    options.trace_rays = &faulty_trace_rays;
    options.user_data = &faulty;
  }

  // --engine gpu: a GpuTracer on the session's device, made once it exists and
  // destroyed before it; its device counters are read then (all work finished).
  std::unique_ptr<foveart::gpu_engine::GpuTracer> gpu_tracer;
  std::optional<foveart::engine::RayCounts> gpu_counts;
  FaultyDeviceEngine faulty_device{nullptr, fault};
  if (gpu_engine) {
    options.make_device_trace = [&](const foveart::hello::VulkanDevice& device) {
      std::string gpu_error;
      gpu_tracer = foveart::gpu_engine::GpuTracer::create(
          foveart::gpu_engine::GpuContext{device.physical_device, device.device, device.queue_family_index,
                                          device.queue},
          std::move(*gpu_scene), {}, &gpu_error);
      if (gpu_tracer == nullptr) throw std::runtime_error("cannot build the GPU ray tracer: " + gpu_error);
      gpu_tracer->reset_counts();
      faulty_device.tracer = gpu_tracer.get();
      if (!fault.empty()) return foveart::hello::DeviceTrace{&faulty_trace_rays_device, &faulty_device};
      return foveart::hello::DeviceTrace{&foveart_gpu_engine_trace_rays_device, gpu_tracer.get()};
    };
    options.release_device_trace = [&]() noexcept {
      if (gpu_tracer == nullptr) return;
      gpu_counts = gpu_tracer->counts();
      gpu_tracer.reset();
    };
  }

  const auto result = foveart::hello::run_app(options);
  if (!result.ok) {
    std::cerr << "hello_foveated: " << result.error << "\n";
    return 1;
  }
  nlohmann::json stats = stats_json(result);
  stats["engine"] = engine_name;
  stats["engine_rays"] = {{"cpu", ray_counts_json(tracer->counts())},
                          {"gpu", gpu_counts ? ray_counts_json(*gpu_counts) : nlohmann::json(nullptr)}};
  if (json) {
    std::cout << stats.dump(2) << "\n";
  } else {
    std::printf("hello_foveated: %llu frames submitted, %llu traced, %llu views fell back; %s engine, reconstruction "
                "on the %s, temporal \"%s\"\n",
                static_cast<unsigned long long>(result.frames),
                static_cast<unsigned long long>(result.stats.framesTraced),
                static_cast<unsigned long long>(result.stats.framesFallback), gpu_engine ? "GPU" : "CPU",
                stats["reconstruction"].get<std::string>() == "gpu" ? "GPU" : "CPU",
                stats["temporal"].get<std::string>().c_str());
  }
  return 0;
}
