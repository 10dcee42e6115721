// What hello_foveated reports: the JSON of a session (--json), and the short
// summaries printed without it.
// --json prints, besides the layer's stats: "engine" (cpu | gpu) and "engine_rays"
// {"cpu": {primary, shadow, reflection, refraction}, "gpu": {...} or null}: the
// rays each engine traced for the layer during the session (the CPU engine's
// counts exclude the exposure pre-pass; the GPU engine's are its device counters),
// and "gpu_engine" (null with --engine cpu): {"device", "backend", "batch": {footprints,
// addresses} (what the layer's last batch chained: GpuTracer::last_batch_chain()), "memory":
// {device_local_bytes, host_visible_bytes, texture_bytes, fallback} (memory_use(),
// memory_fallback()), "work": {bvh_nodes, triangle_tests, bvh_node_count} with
// --count-work on the compute backend, else null}. Its "per_frame" adds
// "end_frame_host_ms" (the host wall time of each xrEndFrame call, steady clock,
// in the app), and on the GPU path, once per finished frame whose times the stats
// held (the newest finished, up to two older): "gpu_trace_ms" [L, R] (the
// device trace's traceMs), "gpu_eye_ms" [L, R] (that plus the GPU stages) and
// "gpu_frame_ms" (both eyes), each {p50, p95, p99, count}; and the series
// end_frame_host_ms_per_frame (per traced frame), gpu_trace_ms_per_frame [L, R]
// and gpu_eye_ms_per_frame [L, R] (per frame with GPU times).
// "density": content density's cost (XrFoveatedRendererDensityStatsFOVEART):
// "eyes" [L, R] of the last frame's {points_thinned, levels_ms, test_ms,
// observe_ms, fill_ms (the CPU trace's host stages), gpu_fill_ms, gpu_contrast_ms
// (the device trace's passes, of the newest finished frame)}; the series
// gpu_fill_ms_per_frame and gpu_contrast_ms_per_frame [L, R] (as gpu_trace_ms);
// and "per_frame": host_ms [L, R] (the host stages' sum per traced frame),
// gpu_fill_ms and gpu_contrast_ms [L, R], each {p50, p95, p99, count}. The summary
// without --json prints an eye's last frame where content density thinned points.
// --json with --mode full: {"mode": "full", "engine", "frames_submitted",
// "frames_rendered", "views", "rays_per_pixel", "rays_per_eye" [L, R] (W * H *
// rays per pixel), "trace_ms_per_eye" [L, R], "trace_ms" (both eyes),
// "frame_ms", "trace_clock" (cpu_wall_clock | gpu_timestamps),
// "transfer_encode_ms_per_eye", "temporal": "off", "history", "display",
// "layer_frames_traced" (0), "layer_views_fallback", "engine_rays"}; the
// times are medians per frame (nearest rank), frame_ms from xrBeginFrame's call
// to xrEndFrame's return. Foveated mode adds "mode": "foveated" and the same
// "rays_per_eye", "trace_ms_per_eye", "trace_ms" (the layer's traceMs),
// "frame_ms", "frames_rendered" over the traced frames, "trace_clock":
// "layer_stats". --mode both prints {"mode": "both", "engine", "full": {...},
// "foveated": {...}, "speedup": {"frame_ms", "trace_ms"}} (full / foveated of
// the medians; null if the foveated one is 0); without --json, a short table.
// --json adds, per traced frame and in the same order: gaze_px_per_frame [frame, left x,
// left y, right x, right y], temporal_reset_per_frame [left, right] (the eye's temporal history
// restarted), gaze_saccade_per_frame / gaze_blink_per_frame (the gaze provider flagged
// a saccade / a blink for it) and display_time_s_per_frame (predicted display time
// after the first traced frame's); temporal_resets counts restarts of both eyes.
#pragma once

#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

#include "engine/tracer.hpp"
#include "foveation/display_transform.hpp"
#include "full_frame.hpp"
#include "gpu_engine/gpu_tracer.hpp"
#include "xr_app.hpp"

namespace foveart::hello {

// {primary, shadow, reflection, refraction}.
nlohmann::json ray_counts_json(const engine::RayCounts& counts);
// "gpu_engine": the device, backend, last batch's chain, memory and traversal work.
nlohmann::json gpu_engine_json(const gpu_engine::GpuTracer& tracer, const std::string& device);
// "app_trace" (--trace-model app).
nlohmann::json app_trace_json(const AppResult& r);
// A foveated session: the layer's stats, its medians and per-frame series.
nlohmann::json foveated_json(const AppResult& r);
// A full session (--mode full): what the app's own render of every pixel cost.
nlohmann::json full_json(const AppResult& r, const FullFrameTimes& times, uint32_t spp,
                         const foveation::DisplayTransform& display, bool gpu);
// full / foveated of the printed medians; null where the foveated one is 0.
nlohmann::json speedup_json(const nlohmann::json& full, const nlohmann::json& foveated);

// Without --json: --mode both's table, a full session's line, a foveated session's lines.
void print_both_table(const nlohmann::json& both);
void print_full_summary(const nlohmann::json& full, bool gpu_engine, uint32_t full_spp);
void print_foveated_summary(const nlohmann::json& foveated, bool gpu_engine);

}  // namespace foveart::hello
