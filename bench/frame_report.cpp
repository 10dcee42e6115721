// The whole frame, both eyes, on a GPU (scripts/bench_gpu.sh; docs/gpu.md
// "Speed"), from two runs of hello_foveated --engine gpu through the real
// OpenXR loader, the layer and the simulated runtime:
//  * the timing run (nothing else loaded): per eye the layer's GPU stage times
//    (trace = device rays + the engine's trace + resolve; gather; temporal;
//    encode with the copy into the swapchain image), the frame's GPU time for
//    both eyes, and the app's host time in xrEndFrame; medians (p50) over the
//    frames the layer traced but the first (the tables' wait, first touches),
//    p95 too for the host time; the GPU times over the frames whose stats held
//    them (the newest finished frame's: the frame is pipelined); whether the
//    slower eye fits 3.5 ms and 7 ms;
//  * the counting run (VK_LAYER_FOVEART_count, --count-work): per frame the
//    submissions, dispatches, barriers and ray-tracing launches the layer and
//    the engine submitted (one steady frame), the rays of each kind and the
//    BVH nodes and triangles visited per ray;
//  * the timing run's content density (on by default on the GPU path): per eye
//    its passes' GPU time (fill, contrast) beside the trace, and the thinned
//    points; with --eccentricity-only, a third run, the timing run's with
//    content density off, whose rays stand beside the timing run's.
// Bytes per stage are the sizes of the buffers the stage binds, computed here
// from the eye size, the points, the rays, the tables' and the scene's bytes
// (gpu_frame's JSON): an upper bound on the distinct bytes a stage touches
// (the trace's repeated BVH reads are its nodes per ray). With --bandwidth-gbs
// and --rays-per-s a predicted time per eye stands beside the measured one.
// Exits 1, naming the device, when the GPU times read 0 (no timestamps).
//   gpu_frame_report --timing FILE --counting FILE --vk-counts FILE --program NAME --frame-json FILE
//                    [--eccentricity-only FILE] [--bandwidth-gbs X] [--rays-per-s Y]
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "foveation/percentile.hpp"
#include "vk_records.hpp"

namespace {

using foveart::foveation::percentile;
using nlohmann::json;

// Buffer element sizes of the layer's device frame (gpu/src/eye.cpp, gpu/src/device_trace.cpp):
constexpr double kRayBytes = 32.0;     // a device ray: origin, direction
constexpr double kColourBytes = 16.0;  // a traced colour, a point's colour, a linear pixel (vec4)
constexpr double kEncodedBytes = 4.0;  // an sRGB RGBA8 texel

struct Inputs {
  json timing, counting, frame, eccentricity_only;  // eccentricity_only: null without --eccentricity-only
  std::vector<json> vk_records;
  std::string program;
  double bandwidth_gbs = 0.0, rays_per_s = 0.0;
};

json read_json(const std::string& path) {
  std::ifstream in(path);
  return json::parse(in, nullptr, false);
}

const char* verdict(double ms, double budget_ms) { return ms <= budget_ms ? "fits" : "misses"; }

// A per-frame series of the timing run without its first frame (the host's: the tables'
// wait; the GPU's: first touches) where there are more; `eye` picks one of [L, R], -1 sums them.
std::vector<double> steady(const json& series, int eye) {
  std::vector<double> v;
  for (std::size_t f = series.size() > 1 ? 1 : 0; f < series.size(); ++f)
    v.push_back(eye < 0 ? (series[f].is_array() ? series[f][0].get<double>() + series[f][1].get<double>()
                                                : series[f].get<double>())
                        : series[f][eye].get<double>());
  return v;
}

// The slower eye's GPU time, p50 over the steady frames.
double eye_ms(const Inputs& in) {
  const json& eyes = in.timing["gpu_eye_ms_per_frame"];
  return std::max(percentile(steady(eyes, 0), 50), percentile(steady(eyes, 1), 50));
}

// Per eye: the stage times (p50 of the trace and the eye, the last frame's reconstruction stages).
void print_times(const Inputs& in) {
  const json& t = in.timing;
  const json& trace = t["gpu_trace_ms_per_frame"];
  const json& eyes = t["gpu_eye_ms_per_frame"];
  const std::vector<double> host = steady(t["end_frame_host_ms_per_frame"], -1);
  std::printf("GPU time per eye (ms)      |     left    right\n");
  std::printf("%-26s | %8.2f %8.2f\n", "trace (p50)", percentile(steady(trace, 0), 50),
              percentile(steady(trace, 1), 50));
  for (const char* stage : {"scatter", "gather", "temporal", "encode"})
    std::printf("%-26s | %8.2f %8.2f\n", (std::string(stage) + (std::string(stage) == "encode" ? " + copy" : "")).c_str(),
                t["gpu_stage_ms"][0].value(stage, 0.0), t["gpu_stage_ms"][1].value(stage, 0.0));
  std::printf("%-26s | %8.2f %8.2f\n", "eye total (p50)", percentile(steady(eyes, 0), 50),
              percentile(steady(eyes, 1), 50));
  std::printf("frame, both eyes: GPU %.2f ms (p50 of %zu frames with GPU times, the first left out); host time in "
              "xrEndFrame p50 %.2f ms, p95 %.2f ms (of %zu frames, the first left out)\n",
              percentile(steady(eyes, -1), 50), steady(eyes, -1).size(), percentile(host, 50), percentile(host, 95),
              host.size());
  const double worst_eye = eye_ms(in);
  std::printf("slower eye %.2f ms: %s 3.5 ms per eye (half a 70 Hz frame for two eyes), %s 7 ms per eye (two eyes "
              "in a 70 Hz frame)\n",
              worst_eye, verdict(worst_eye, 3.5), verdict(worst_eye, 7.0));
}

// One steady frame's work of the layer and the engine, from the counting run's Vulkan record.
void print_submitted_work(const Inputs& in) {
  const foveart::vk_count::Roles roles{in.program};
  for (const json& record : in.vk_records) {
    // The app's placeholder clear, one submission per eye, marks the frames (as vk_count_test does).
    const auto frames = foveart::vk_count::split_frames_of<foveart::vk_count::Work>(
        record, roles, [](const json& e, const std::string& who) { return who == "app" && e["call"] == "vkQueueSubmit"; },
        2);
    const auto tallies = foveart::vk_count::split_frames(
        record, roles, [](const json& e, const std::string& who) { return who == "app" && e["call"] == "vkQueueSubmit"; },
        2);
    if (frames.empty() || tallies.empty()) continue;
    foveart::vk_count::Work w;
    for (const char* who : {"layer", "engine"})
      if (auto it = frames.back().find(who); it != frames.back().end()) w.add(it->second);
    const foveart::vk_count::Tally t = foveart::vk_count::sum(tallies.back(), {"layer", "engine"});
    std::printf("submitted per frame, both eyes (layer + engine, the last complete of %zu frames): %llu submissions, "
                "%llu command buffers, %llu dispatches, %llu indirect dispatches, %llu pipeline barriers, %llu "
                "ray-tracing launches\n",
                frames.size(), static_cast<unsigned long long>(t.submissions),
                static_cast<unsigned long long>(t.command_buffers), static_cast<unsigned long long>(w.dispatches),
                static_cast<unsigned long long>(w.dispatches_indirect), static_cast<unsigned long long>(w.barriers),
                static_cast<unsigned long long>(w.trace_rays));
    return;
  }
  std::printf("submitted per frame: no complete frame in the Vulkan record\n");
}

// Rays of each kind per frame and the traversal's work per ray, from the counting run.
double print_rays(const Inputs& in) {
  const json& c = in.counting;
  const double frames = std::max(1.0, c.value("frames_traced", 1.0));
  const json& rays = c["engine_rays"]["gpu"];
  if (!rays.is_object()) return 0.0;
  const double primary = rays.value("primary", 0.0), shadow = rays.value("shadow", 0.0),
               reflection = rays.value("reflection", 0.0), refraction = rays.value("refraction", 0.0);
  const double total = primary + shadow + reflection + refraction;
  std::printf("rays per frame, both eyes: %.0f primary, %.0f shadow, %.0f reflection, %.0f refraction (%.0f)\n",
              primary / frames, shadow / frames, reflection / frames, refraction / frames, total / frames);
  const json& work = c["gpu_engine"]["work"];
  if (work.is_object() && total > 0.0) {
    std::printf("traversal per ray: %.1f BVH nodes visited (of %.0f), %.1f triangles tested\n",
                work.value("bvh_nodes", 0.0) / total, work.value("bvh_node_count", 0.0),
                work.value("triangle_tests", 0.0) / total);
  } else {
    std::printf("traversal per ray: n/a (the %s backend's traversal is the driver's)\n",
                c["gpu_engine"].value("backend", std::string("?")).c_str());
  }
  return total / frames;
}

struct EyeBytes {
  double trace = 0, gather = 0, temporal = 0, encode = 0;
  double total() const { return trace + gather + temporal + encode; }
};

// One eye's bytes bound per stage: the buffers as the stage binds them.
EyeBytes eye_bytes(const Inputs& in, int e) {
  const json& view = in.timing["views"][e];
  const double pixels = view["size_px"][0].get<double>() * view["size_px"][1].get<double>();
  const double points = in.timing["eyes"][e].value("points", 0.0), rays = in.timing["eyes"][e].value("rays", 0.0);
  const json& memory = in.frame["memory"];
  const double scene = memory.value("device_local_bytes", 0.0) + memory.value("host_visible_bytes", 0.0);
  EyeBytes b;
  // Rays written and read, colours written and read, a colour per point resolved; the scene once.
  b.trace = rays * 2 * kRayBytes + rays * 2 * kColourBytes + points * kColourBytes + scene;
  b.gather = in.frame.value("table_bytes", 0.0) + points * kColourBytes + pixels * kColourBytes;
  b.temporal = pixels * kColourBytes * 3;  // the current image and the history read, the history written
  b.encode = pixels * kColourBytes + pixels * kEncodedBytes * 3;  // encoded written, read by the copy, image written
  return b;
}

// Bytes bound per stage and the predicted time per eye beside the measured one.
void print_bytes_and_prediction(const Inputs& in, double rays_per_frame) {
  const EyeBytes b = eye_bytes(in, 0);
  std::printf("bytes bound per eye (MB; buffer sizes, an upper bound on the bytes touched): trace %.1f, gather %.1f, "
              "temporal %.1f, encode + copy %.1f, total %.1f\n",
              b.trace * 1e-6, b.gather * 1e-6, b.temporal * 1e-6, b.encode * 1e-6, b.total() * 1e-6);
  const double measured = eye_ms(in);
  if (in.frame.value("device_is_cpu", false) || in.bandwidth_gbs <= 0.0 || in.rays_per_s <= 0.0) {
    std::printf("predicted per eye: n/a (%s); measured %.2f ms\n",
                in.frame.value("device_is_cpu", false) ? "a CPU device"
                                                       : "give --bandwidth-gbs and --rays-per-s for this device",
                measured);
    return;
  }
  const double bytes_ms = b.total() / (in.bandwidth_gbs * 1e9) * 1e3;
  const double rays_ms = rays_per_frame / 2.0 / in.rays_per_s * 1e3;
  std::printf("predicted per eye at %.0f GB/s and %.3g rays/s: %.2f ms (bytes %.2f + rays %.2f); measured %.2f ms\n",
              in.bandwidth_gbs, in.rays_per_s, bytes_ms + rays_ms, bytes_ms, rays_ms, measured);
}

// Content density's passes per eye (p50 over the steady frames) beside the timing run's trace,
// and its rays beside the eccentricity-only run's: the newest finished frame's of each.
void print_density(const Inputs& in) {
  const json& d = in.timing;
  const json& stats = d["density"];
  if (!stats.is_object()) {
    std::printf("content density: the timing run reported no density stats\n");
    return;
  }
  std::printf("content density, the timing run's passes per eye (p50 of the frames with GPU times, the first left "
              "out):\n");
  double rays_on = 0.0, rays_off = 0.0;
  for (int e = 0; e < 2; ++e) {
    const double fill = percentile(steady(stats["gpu_fill_ms_per_frame"], e), 50);
    const double contrast = percentile(steady(stats["gpu_contrast_ms_per_frame"], e), 50);
    const double trace = percentile(steady(d["gpu_trace_ms_per_frame"], e), 50);
    std::printf("  eye %d: fill %.3f ms + contrast %.3f ms = %.1f %% of its trace (%.2f ms); %.0f points thinned\n", e,
                fill, contrast, trace > 0.0 ? (fill + contrast) / trace * 100.0 : 0.0, trace,
                stats["eyes"][e].value("points_thinned", 0.0));
    rays_on += d["eyes"][e].value("rays", 0.0);
    if (in.eccentricity_only.is_object()) rays_off += in.eccentricity_only["eyes"][e].value("rays", 0.0);
  }
  if (!in.eccentricity_only.is_object()) return;
  std::printf("  rays, both eyes: %.0f with content density, %.0f with eccentricity only (%.1f %%)\n", rays_on,
              rays_off, rays_off > 0.0 ? rays_on / rays_off * 100.0 : 0.0);
}

// The GPU times must be real: 0 ms means the device gave no timestamps.
bool times_measured(const Inputs& in) {
  if (in.timing.value("reconstruction", std::string()) != "gpu" || !(eye_ms(in) > 0.0)) {
    std::fprintf(stderr,
                 "gpu_frame_report: %s: the layer's GPU times read 0 (reconstruction \"%s\"): no timestamps, or "
                 "the frames did not run on the GPU path; nothing to report\n",
                 in.frame.value("device", std::string("the device")).c_str(),
                 in.timing.value("reconstruction", std::string("?")).c_str());
    return false;
  }
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App cli{"The whole frame, both eyes, on a GPU: times, work and bytes from two hello_foveated runs"};
  Inputs in;
  std::string timing, counting, vk_counts, frame;
  cli.add_option("--timing", timing, "hello_foveated --json of the timing run")->required();
  cli.add_option("--counting", counting, "hello_foveated --json of the counting run (--count-work)")->required();
  cli.add_option("--vk-counts", vk_counts, "VK_LAYER_FOVEART_count's output of the counting run")->required();
  cli.add_option("--program", in.program, "the app's file name (hello_foveated)")->required();
  cli.add_option("--frame-json", frame, "gpu_frame --json (device, table and scene bytes)")->required();
  std::string eccentricity_only;
  cli.add_option("--eccentricity-only", eccentricity_only,
                 "hello_foveated --json of the timing run with content density off (\"content_contrast\": 0)");
  cli.add_option("--bandwidth-gbs", in.bandwidth_gbs, "the device's memory bandwidth, GB/s (for a prediction)");
  cli.add_option("--rays-per-s", in.rays_per_s, "the engine's rays per second on the device (for a prediction)");
  CLI11_PARSE(cli, argc, argv);
  in.timing = read_json(timing);
  in.counting = read_json(counting);
  in.frame = read_json(frame);
  in.vk_records = foveart::vk_count::read_records(vk_counts);
  if (!eccentricity_only.empty()) in.eccentricity_only = read_json(eccentricity_only);
  if (!in.timing.is_object() || !in.counting.is_object() || !in.frame.is_object() ||
      (!eccentricity_only.empty() && !in.eccentricity_only.is_object())) {
    std::fprintf(stderr, "gpu_frame_report: cannot read %s, %s, %s or %s as JSON\n", timing.c_str(), counting.c_str(),
                 frame.c_str(), eccentricity_only.empty() ? "(no --eccentricity-only)" : eccentricity_only.c_str());
    return 1;
  }
  if (!times_measured(in)) return 1;
  const json& view = in.timing["views"][0];
  const std::string device = in.timing["gpu_engine"].value("device", std::string("?"));
  if (device != in.frame.value("device", std::string("?")))
    std::printf("NOTE: the OpenXR session ran on %s, gpu_frame on %s\n", device.c_str(),
                in.frame.value("device", std::string("?")).c_str());
  std::printf("whole frame: %s, %dx%d per eye, engine backend %s, temporal %s\n", device.c_str(),
              view["size_px"][0].get<int>(),
              view["size_px"][1].get<int>(), in.counting["gpu_engine"].value("backend", std::string("?")).c_str(),
              in.timing.value("temporal", std::string("?")).c_str());
  print_times(in);
  print_submitted_work(in);
  const double rays_per_frame = print_rays(in);
  print_bytes_and_prediction(in, rays_per_frame);
  print_density(in);
  return 0;
}
