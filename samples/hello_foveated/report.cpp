#include "report.hpp"

#include <algorithm>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "foveation/percentile.hpp"

namespace foveart::hello {
namespace {

using foveation::percentile;

const char* gaze_source_name(XrFoveatedGazeSourceFOVEART s) {
  switch (s) {
    case XR_FOVEATED_GAZE_SOURCE_PROVIDER_FOVEART: return "provider";
    case XR_FOVEATED_GAZE_SOURCE_EYE_GAZE_INTERACTION_FOVEART: return "eye_gaze_interaction";
    default: return "none";
  }
}

nlohmann::json distribution(const std::vector<float>& v) {
  return {{"p50", percentile(v, 50)}, {"p95", percentile(v, 95)}, {"p99", percentile(v, 99)}, {"count", v.size()}};
}

// The last frame's submitted views: pose (the scene's space), FOV, size.
nlohmann::json views_json(const AppResult& r) {
  nlohmann::json views = nlohmann::json::array();
  for (const auto& v : r.views) {
    views.push_back({{"position_m", {v.pose.position.x, v.pose.position.y, v.pose.position.z}},
                     {"orientation_xyzw",
                      {v.pose.orientation.x, v.pose.orientation.y, v.pose.orientation.z, v.pose.orientation.w}},
                     {"fov_rad", {v.fov.angleLeft, v.fov.angleRight, v.fov.angleUp, v.fov.angleDown}},
                     {"size_px", {v.width_px, v.height_px}}});
  }
  return views;
}

// [left, right] distributions of two per-eye series.
nlohmann::json eye_distributions(const std::vector<float>* per_eye) {
  return {distribution(per_eye[0]), distribution(per_eye[1])};
}

// Per traced frame [left, right] of two per-eye series.
nlohmann::json eye_pairs(const std::vector<float>* per_eye) {
  nlohmann::json pairs = nlohmann::json::array();
  for (std::size_t f = 0; f < std::min(per_eye[0].size(), per_eye[1].size()); ++f)
    pairs.push_back({per_eye[0][f], per_eye[1][f]});
  return pairs;
}

// Content density's cost per eye (XrFoveatedRendererDensityStatsFOVEART): the last frame's
// stages (host on a CPU trace, GPU on a device trace, the newest finished frame), and per frame.
nlohmann::json density_json(const AppResult& r) {
  const auto& d = r.density;
  nlohmann::json eyes = nlohmann::json::array();
  for (int e = 0; e < 2; ++e) {
    eyes.push_back({{"points_thinned", d.pointsThinned[e]},
                    {"levels_ms", d.levelsMs[e]},
                    {"test_ms", d.testMs[e]},
                    {"observe_ms", d.observeMs[e]},
                    {"fill_ms", d.fillMs[e]},
                    {"gpu_fill_ms", d.gpuFillMs[e]},
                    {"gpu_contrast_ms", d.gpuContrastMs[e]}});
  }
  return {{"eyes", eyes},
          {"gpu_fill_ms_per_frame", eye_pairs(r.gpu_density_fill_ms)},
          {"gpu_contrast_ms_per_frame", eye_pairs(r.gpu_density_contrast_ms)},
          {"per_frame",
           {{"host_ms", eye_distributions(r.density_ms)},
            {"gpu_fill_ms", eye_distributions(r.gpu_density_fill_ms)},
            {"gpu_contrast_ms", eye_distributions(r.gpu_density_contrast_ms)}}}};
}

nlohmann::json stats_json(const AppResult& r) {
  const auto& s = r.stats;
  nlohmann::json eyes = nlohmann::json::array();
  for (int e = 0; e < 2; ++e) {
    eyes.push_back({{"points", s.pointsPerEye[e]},
                    {"rays", s.raysPerEye[e]},
                    {"select_ms", s.selectMs[e]},
                    {"trace_ms", s.traceMs[e]},
                    {"reconstruct_ms", s.reconstructMs[e]},
                    {"temporal_ms", s.temporalMs[e]},
                    {"upload_ms", s.uploadMs[e]}});
  }
  const auto& rec = r.reconstruction;
  nlohmann::json gpu_ms = nlohmann::json::array();
  for (int e = 0; e < 2; ++e) {
    gpu_ms.push_back({{"scatter", rec.gpuScatterMs[e]},
                      {"gather", rec.gpuGatherMs[e]},
                      {"temporal", rec.gpuTemporalMs[e]},
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
  nlohmann::json temporal_reset = nlohmann::json::array();
  for (const auto& frame : r.temporal_reset) {
    nlohmann::json pair = nlohmann::json::array();
    pair.push_back(frame[0]);
    pair.push_back(frame[1]);
    temporal_reset.push_back(std::move(pair));
  }
  nlohmann::json views = views_json(r);
  return {{"frames_submitted", r.frames},
          {"views", views},
          {"frames_traced", s.framesTraced},
          {"views_fallback", s.framesFallback},
          {"eyes", eyes},
          {"reconstruction", path},
          {"temporal", temporal},
          {"gpu_stage_ms", gpu_ms},
          {"gpu_fallbacks", rec.gpuFallbacks},
          {"density", density_json(r)},
          {"gaze_age_ms", s.gazeAgeMs},
          {"gaze_source", gaze_source_name(s.gazeSource)},
          {"fallback_flags", s.fallbackFlags},
          {"callback_failures", s.callbackFailures},
          {"invalid_colours", s.invalidColours},
          {"gaze_lost_frames", s.gazeLostFrames},
          {"gaze_px_per_frame", r.gaze_px},
          {"end_frame_host_ms_per_frame", r.end_frame_host_ms},
          {"gpu_trace_ms_per_frame", eye_pairs(r.gpu_trace_ms)},
          {"gpu_eye_ms_per_frame", eye_pairs(r.gpu_eye_ms)},
          {"temporal_resets", rec.temporalResets},
          {"temporal_reset_per_frame", temporal_reset},
          {"gaze_saccade_per_frame", r.gaze_saccade},
          {"gaze_blink_per_frame", r.gaze_blink},
          {"display_time_s_per_frame", r.display_time_s},
          {"app_gaze_located_frames", r.app_gaze_located_frames},
          {"per_frame",
           {{"gaze_age_ms", distribution(r.gaze_age_ms)},
            {"layer_overhead_ms", eye_distributions(r.overhead_ms)},
            {"trace_ms", eye_distributions(r.trace_ms)},
            {"gpu_trace_ms", eye_distributions(r.gpu_trace_ms)},
            {"gpu_eye_ms", eye_distributions(r.gpu_eye_ms)},
            {"gpu_frame_ms", distribution(r.gpu_frame_ms)},
            {"end_frame_host_ms", distribution(r.end_frame_host_ms)}}}};
}

// The medians of a mode: per eye and of each frame's both eyes (nearest rank).
nlohmann::json medians_json(const std::vector<float>* per_eye_trace_ms, const std::vector<float>& frame_ms) {
  std::vector<float> both;
  for (std::size_t f = 0; f < std::min(per_eye_trace_ms[0].size(), per_eye_trace_ms[1].size()); ++f)
    both.push_back(per_eye_trace_ms[0][f] + per_eye_trace_ms[1][f]);
  return {{"trace_ms_per_eye", {percentile(per_eye_trace_ms[0], 50), percentile(per_eye_trace_ms[1], 50)}},
          {"trace_ms", percentile(both, 50)},
          {"frame_ms", percentile(frame_ms, 50)},
          {"frames_rendered", frame_ms.size()}};
}

}  // namespace

nlohmann::json ray_counts_json(const engine::RayCounts& c) {
  return {{"primary", c.primary}, {"shadow", c.shadow}, {"reflection", c.reflection}, {"refraction", c.refraction}};
}

// What the GPU engine holds on the device and, with --count-work, its traversal's work.
nlohmann::json gpu_engine_json(const gpu_engine::GpuTracer& tracer, const std::string& device) {
  const gpu_engine::MemoryUse m = tracer.memory_use();
  const gpu_engine::WorkCounts w = tracer.work_counts();
  const gpu_engine::BatchChain chain = tracer.last_batch_chain();
  return {{"device", device},
          {"backend", tracer.backend_name()},
          {"batch", {{"footprints", chain.footprints}, {"addresses", chain.addresses}}},
          {"memory", {{"device_local_bytes", m.device_local_bytes},
                      {"host_visible_bytes", m.host_visible_bytes},
                      {"texture_bytes", m.texture_bytes},
                      {"fallback", tracer.memory_fallback()}}},
          {"work", w.counted ? nlohmann::json{{"bvh_nodes", w.bvh_nodes},
                                              {"triangle_tests", w.triangle_tests},
                                              {"bvh_node_count", tracer.bvh_node_count()}}
                             : nlohmann::json(nullptr)}};
}

// --trace-model app: the layer's counts and the rays' extra gaze age.
nlohmann::json app_trace_json(const AppResult& r) {
  const auto& a = r.app_trace;
  return {{"batches_acquired", a.batchesAcquired},
          {"unreleased_batches", a.unreleasedBatches},
          {"rejected_releases", a.rejectedReleases},
          {"mismatched_views", a.mismatchedViews},
          {"release_errors", r.release_errors},
          {"last_release_error", r.last_release_error},
          {"second_queue", r.second_queue},
          {"acquire_to_end_frame_ms", distribution(r.acquire_to_end_frame_ms)}};
}

// stats_json and, to compare with --mode full, the medians over the traced frames.
nlohmann::json foveated_json(const AppResult& r) {
  nlohmann::json out = stats_json(r);
  const nlohmann::json medians = medians_json(r.trace_ms, r.frame_ms);
  for (const auto& item : medians.items()) out[item.key()] = item.value();
  out["rays_per_eye"] = {r.stats.raysPerEye[0], r.stats.raysPerEye[1]};
  out["trace_clock"] = "layer_stats";
  return out;
}

// --mode full: what the app's own render of every pixel cost, and that the layer stayed out.
nlohmann::json full_json(const AppResult& r, const FullFrameTimes& times,
                         uint32_t spp, const foveation::DisplayTransform& display, bool gpu) {
  nlohmann::json views = views_json(r);
  nlohmann::json out = medians_json(times.trace_ms, r.frame_ms);
  nlohmann::json rays = nlohmann::json::array();
  for (const auto& v : r.views) rays.push_back(uint64_t(v.width_px) * uint64_t(v.height_px) * spp);
  out["frames_submitted"] = r.frames;
  out["views"] = std::move(views);
  out["rays_per_pixel"] = spp;
  out["rays_per_eye"] = std::move(rays);
  out["temporal"] = "off";  // a full render keeps nothing from earlier frames
  out["history"] = "none: each frame is traced anew with the same seed";
  out["trace_clock"] = gpu ? "gpu_timestamps" : "cpu_wall_clock";
  out["transfer_encode_ms_per_eye"] = {percentile(times.transfer_encode_ms[0], 50),
                                       percentile(times.transfer_encode_ms[1], 50)};
  out["display"] = {{"exposure", display.exposure}, {"tone_map", foveation::tone_map_name(display.tone_map)}};
  out["layer_frames_traced"] = r.stats.framesTraced;
  out["layer_views_fallback"] = r.stats.framesFallback;
  return out;
}

// full / foveated of the printed medians; null where the foveated one is 0.
nlohmann::json speedup_json(const nlohmann::json& full, const nlohmann::json& foveated) {
  const auto ratio = [&](const char* key) {
    const double f = full[key].get<double>(), v = foveated[key].get<double>();
    return v > 0.0 ? nlohmann::json(f / v) : nlohmann::json(nullptr);
  };
  return {{"frame_ms", ratio("frame_ms")}, {"trace_ms", ratio("trace_ms")}};
}

void print_both_table(const nlohmann::json& both) {
  const auto& full = both["full"];
  const auto& fov = both["foveated"];
  const auto size = full["views"][0]["size_px"];
  std::printf("hello_foveated --mode both: %s engine, %dx%d per eye, medians per frame\n",
              both["engine"].get<std::string>().c_str(), size[0].get<int>(), size[1].get<int>());
  std::printf("  %-9s %12s %18s %12s %12s\n", "mode", "frame ms", "trace ms (2 eyes)", "rays/eye L", "rays/eye R");
  for (const auto* row : {&full, &fov}) {
    std::printf("  %-9s %12.2f %18.2f %12llu %12llu\n", (*row)["mode"].get<std::string>().c_str(),
                (*row)["frame_ms"].get<double>(), (*row)["trace_ms"].get<double>(),
                static_cast<unsigned long long>((*row)["rays_per_eye"][0].get<uint64_t>()),
                static_cast<unsigned long long>((*row)["rays_per_eye"][1].get<uint64_t>()));
  }
  const auto x = [](const nlohmann::json& v) { return v.is_null() ? 0.0 : v.get<double>(); };
  std::printf("  %-9s %11.2fx %17.2fx   (full / foveated)\n", "speedup", x(both["speedup"]["frame_ms"]),
              x(both["speedup"]["trace_ms"]));
}

void print_full_summary(const nlohmann::json& f, bool gpu_engine, uint32_t full_spp) {
  std::printf(
      "hello_foveated: full render, %s engine: %llu frames, %u ray(s) per pixel, median frame %.2f ms, "
      "trace %.2f ms (both eyes, %s)\n",
      gpu_engine ? "GPU" : "CPU", static_cast<unsigned long long>(f["frames_submitted"].get<uint64_t>()), full_spp,
      f["frame_ms"].get<double>(), f["trace_ms"].get<double>(), f["trace_clock"].get<std::string>().c_str());
}

void print_foveated_summary(const nlohmann::json& st, bool gpu_engine) {
  std::printf(
      "hello_foveated: %llu frames submitted, %llu traced, %llu views fell back; %s engine, reconstruction "
      "on the %s, temporal \"%s\"\n",
      static_cast<unsigned long long>(st["frames_submitted"].get<uint64_t>()),
      static_cast<unsigned long long>(st["frames_traced"].get<uint64_t>()),
      static_cast<unsigned long long>(st["views_fallback"].get<uint64_t>()), gpu_engine ? "GPU" : "CPU",
      st["reconstruction"].get<std::string>() == "gpu" ? "GPU" : "CPU", st["temporal"].get<std::string>().c_str());
  for (int e = 0; e < 2; ++e) {  // content density's last frame, where it thinned
    const nlohmann::json& d = st["density"]["eyes"][e];
    if (d["points_thinned"].get<uint64_t>() == 0) continue;
    std::printf("  %s eye, content density: %llu points thinned; host ms levels %.2f, test %.2f, observe %.2f, "
                "fill %.2f; device ms fill %.3f, contrast %.3f\n",
                e == 0 ? "left" : "right", static_cast<unsigned long long>(d["points_thinned"].get<uint64_t>()),
                d["levels_ms"].get<double>(), d["test_ms"].get<double>(), d["observe_ms"].get<double>(),
                d["fill_ms"].get<double>(), d["gpu_fill_ms"].get<double>(), d["gpu_contrast_ms"].get<double>());
  }
}

}  // namespace foveart::hello
