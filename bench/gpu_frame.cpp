// The whole frame of one eye on a GPU, in one run on one Vulkan device
// (scripts/bench_gpu.sh; docs/gpu.md "Speed"): the GPU sample engine
// (samples/gpu_engine) traces a scene
//  * full: every pixel, --spp rays each (GpuTracer::record_full), the fair
//    baseline: the same engine, and the same temporal history and encode
//    passes on the same pixels as the foveated frame (their times are taken
//    from it: the full frame = its trace + the foveated frame's history and
//    encode);
//  * foveated: the layer's device path: rays made on the device, the engine's
//    device trace, the resolve, gather, history and encode (gpu::Eye with a
//    DeviceTraceFrame), each stage from timestamps ("trace" is rays + the
//    engine's trace + resolve).
// Median over --frames frames after one warm-up; speedup = full / foveated
// per frame pair, median. A discrete or integrated GPU when there is one,
// else lavapipe (a CPU: there only the ratio means anything). The engine runs
// as a ray-tracing pipeline where the device offers VK_KHR_ray_tracing_pipeline,
// else as a compute shader; the output and the JSON say which ("backend").
// Fails, naming the device, where its queue has no timestamps or they read 0
// (gpu_engine/timestamps.hpp): no 0 ms medians. Also prints the engine's memory
// (device-local or forced host-visible), the rays of each kind per frame, and
// whether the foveated eye fits 3.5 ms and 7 ms (70 Hz, two eyes).
//   gpu_frame [--scene default|room|hall|dense|FILE] [--size W H] [--frames N (8; 2 on a CPU device)]
//             [--spp N] [--temporal off|image] [--k K] [--json FILE]
// Tables come from $FOVEART_BENCH_CACHE (default /tmp/foveart_bench_cache).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "engine/gltf_loader.hpp"
#include "engine/render.hpp"
#include "foveation/foveated_view.hpp"
#include "foveation/temporal_mode.hpp"
#include "foveation/view_settings.hpp"
#include "foveation/view_tables.hpp"
#include "gpu_engine/gpu_tracer.hpp"
#include "gpu_engine/rt_device.hpp"
#include "gpu_engine/timestamps.hpp"
#include "device_trace_engine.hpp"
#include "gpu/reconstructor.hpp"
#include "headless_vulkan.hpp"

namespace {

namespace fv = foveart::foveation;
namespace layer = foveart::layer;

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

int fail(const std::string& message) {
  std::fprintf(stderr, "gpu_frame: %s\n", message.c_str());
  return 1;
}

// Two timestamps around the full render.
class FullTimer {
 public:
  FullTimer(VkDevice device, float period_ns) : device_(device), period_ns_(period_ns) {
    VkQueryPoolCreateInfo info{};
    info.sType = VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO;
    info.queryType = VK_QUERY_TYPE_TIMESTAMP;
    info.queryCount = 2;
    if (vkCreateQueryPool(device, &info, nullptr, &pool_) != VK_SUCCESS) pool_ = VK_NULL_HANDLE;
  }
  ~FullTimer() {
    if (pool_ != VK_NULL_HANDLE) vkDestroyQueryPool(device_, pool_, nullptr);
  }
  FullTimer(const FullTimer&) = delete;
  FullTimer& operator=(const FullTimer&) = delete;
  bool ok() const { return pool_ != VK_NULL_HANDLE; }
  void begin(VkCommandBuffer cb) const {
    vkCmdResetQueryPool(cb, pool_, 0, 2);
    vkCmdWriteTimestamp(cb, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, pool_, 0);
  }
  void end(VkCommandBuffer cb) const { vkCmdWriteTimestamp(cb, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, pool_, 1); }
  // The two stamps of the finished submission; false when they cannot be read.
  bool stamps(uint64_t (&t)[2]) const {
    return vkGetQueryPoolResults(device_, pool_, 0, 2, sizeof t, t, sizeof(uint64_t), VK_QUERY_RESULT_64_BIT) ==
           VK_SUCCESS;
  }
  double ms() const {
    uint64_t t[2] = {};
    if (!stamps(t)) return -1.0;
    return double(t[1] - t[0]) * double(period_ns_) * 1e-6;
  }

 private:
  VkDevice device_;
  float period_ns_;
  VkQueryPool pool_ = VK_NULL_HANDLE;
};

}  // namespace

int main(int argc, char** argv) {
  CLI::App cli{"One eye's full and foveated frame on the GPU sample engine, per stage, in one run"};
  std::string scene_spec = "default";
  std::vector<int> size{1280, 1440};
  int frames = 0, spp = 1, k = 5;
  std::string temporal = "image", json_path;
  cli.add_option("--scene", scene_spec, "default, room, hall, dense or a glTF file")->capture_default_str();
  cli.add_option("--size", size, "eye size W H (the FOVE eye's FOV)")->expected(2)->check(CLI::Range(16, 8192))
      ->capture_default_str();
  cli.add_option("--frames", frames, "frames timed after one warm-up (default: 8 on a GPU, 2 on a CPU device)")
      ->check(CLI::Range(1, 1000));
  cli.add_option("--spp", spp, "rays per pixel (full) and per point (foveated)")->check(CLI::Range(1, 64))
      ->capture_default_str();
  cli.add_option("--k", k, "MSM neighbours per pixel")->check(CLI::Range(1, 20))->capture_default_str();
  cli.add_option("--temporal", temporal, "off | image: the history both frames keep")
      ->check(CLI::IsMember({"off", "image"}))
      ->capture_default_str();
  cli.add_option("--json", json_path, "also write the results as JSON to this file");
  CLI11_PARSE(cli, argc, argv);

  auto loaded = foveart::engine::load_scene(scene_spec);
  if (!loaded.ok()) return fail(loaded.error);
  const foveart::engine::Camera head = foveart::engine::scene_head(*loaded.scene);
  FoveartEyeView view = foveart::engine::fove_eye_view(0, head);
  view.width_px = uint32_t(size[0]);
  view.height_px = uint32_t(size[1]);

  // The GPU engine's ray-tracing pipeline backend where the device offers it (else compute).
  std::unique_ptr<foveart::gpu_engine::RayTracingDeviceSupport> rt_support;
  std::vector<const char*> rt_extensions;
  bool ray_tracing = false;
  layer::HeadlessVulkan vulkan(layer::DevicePreference::hardware_gpu, false,
                               [&](VkPhysicalDevice physical, VkDeviceCreateInfo* info) {
                                 rt_support = std::make_unique<foveart::gpu_engine::RayTracingDeviceSupport>(physical);
                                 ray_tracing = rt_support->enable(info, &rt_extensions);
                               });
  if (!vulkan.ok()) return fail("no Vulkan device with a compute queue");
  if (frames == 0) frames = vulkan.is_cpu() ? 2 : 8;  // lavapipe traces a FOVE eye in tens of seconds
  const foveart::gpu::Device device = vulkan.device();
  std::string error;
  auto gpu = foveart::gpu::Reconstructor::create(device, &error);
  if (gpu == nullptr) return fail(vulkan.name() + " cannot run the shaders: " + error);
  VkQueue queue = VK_NULL_HANDLE;
  vkGetDeviceQueue(device.device, device.queue_family_index, device.queue_index, &queue);
  foveart::gpu_engine::GpuContext context{device.physical_device, device.device, device.queue_family_index, queue};
  context.ray_tracing_enabled = ray_tracing;
  auto tracer = foveart::gpu_engine::GpuTracer::create(context, std::move(*loaded.scene), {}, &error);
  if (tracer == nullptr) return fail("GPU engine: " + error);
  VkPhysicalDeviceProperties properties{};
  vkGetPhysicalDeviceProperties(device.physical_device, &properties);
  const std::string no_timestamps =
      foveart::gpu_engine::timestamp_support_problem(device.physical_device, device.queue_family_index);
  if (!no_timestamps.empty()) return fail(no_timestamps);
  FullTimer full_timer(device.device, properties.limits.timestampPeriod);
  if (!full_timer.ok()) return fail("no timestamp query pool");

  fv::Executor executor;
  const char* env_cache = std::getenv("FOVEART_BENCH_CACHE");
  const std::filesystem::path cache = env_cache != nullptr ? env_cache : "/tmp/foveart_bench_cache";
  fv::PointSetKey key;
  key.display = fv::display_of_view(view);
  key.seed = 1;
  fv::InterpOptions interp;
  interp.method = fv::InterpMethod::msm;
  interp.k = k;
  std::fprintf(stderr, "gpu_frame: tables for %dx%d, MSM k %d (cached in %s) ...\n", size[0], size[1], k,
               cache.c_str());
  const auto tables = fv::load_view_tables(cache, key, interp, executor);
  fv::TemporalMode mode = temporal == "image" ? fv::TemporalMode::image : fv::TemporalMode::off;
  fv::ViewSettings settings = fv::temporal_view_settings(mode, spp, 1);
  settings.reconstruct_on_cpu = false;
  fv::FoveatedView foveated(tables, settings);
  const auto gpu_tables = gpu->upload_tables(tables, &error);
  auto eye = gpu_tables ? gpu->create_eye(view.width_px, view.height_px, &error) : nullptr;
  if (eye == nullptr) return fail(error);

  foveart::gpu::BoundBuffer full_out;
  VkPhysicalDeviceMemoryProperties memory{};
  vkGetPhysicalDeviceMemoryProperties(device.physical_device, &memory);
  if (!foveart::gpu::create_bound_buffer(device.device, memory, VkDeviceSize{view.width_px} * view.height_px * 16,
                                  VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, foveart::gpu::buffer_memory_flags(false),
                                  &full_out.buffer, &full_out.memory, nullptr, &error)) {
    return fail(error);
  }

  std::printf("gpu_frame: %s, scene %s (%s), eye %dx%d, %d spp, MSM k %d, temporal %s, %d frames; device: %s; "
              "backend: %s\n",
              scene_spec.c_str(), tracer->scene().source.c_str(), foveart::engine::to_string(tracer->effects()).c_str(),
              size[0], size[1], spp, k, temporal.c_str(), frames, vulkan.name().c_str(), tracer->backend_name());
  if (!tracer->backend_fallback().empty()) std::fprintf(stderr, "gpu_frame: %s\n", tracer->backend_fallback().c_str());
  const foveart::gpu_engine::MemoryUse memory_use = tracer->memory_use();
  std::printf("GPU engine memory: %.1f MB device-local, %.1f MB host-visible (textures %.1f MB)%s%s\n",
              double(memory_use.device_local_bytes) * 1e-6, double(memory_use.host_visible_bytes) * 1e-6,
              double(memory_use.texture_bytes) * 1e-6, tracer->memory_fallback().empty() ? "" : "; ",
              tracer->memory_fallback().c_str());
  foveart::engine::RayCounts full_rays, fov_rays;  // of the last frame
  std::vector<double> full_trace, fov_trace, gather, history, encode, full_total, fov_total, ratio, fov_wall, full_wall;
  std::vector<double> points;
  bool ok = true;
  for (int i = 0; i <= frames && ok; ++i) {  // frame 0 warms up
    fv::FrameRequest request;
    request.view = view;
    request.frame_index = uint64_t(i + 1);
    request.gaze_px = {float(size[0] / 2 + (i % 3)), float(size[1] / 2)};
    const auto t_full = std::chrono::steady_clock::now();
    tracer->reset_counts();
    ok = gpu->submit_and_wait(
        [&](VkCommandBuffer cb) {
          full_timer.begin(cb);
          const bool recorded =
              tracer->record_full(cb, view, uint32_t(spp), settings.frame_sample_seed(request.frame_index),
                                  full_out.buffer, 0, &error);
          full_timer.end(cb);
          return recorded;
        },
        &error);
    const double full_wall_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t_full).count();
    if (!ok) break;
    const double full_ms = full_timer.ms();
    uint64_t stamps[2] = {};
    error = full_timer.stamps(stamps) ? foveart::gpu_engine::timestamp_reading_problem(vulkan.name(), stamps[0], stamps[1])
                                      : vulkan.name() + ": its timestamps cannot be read";
    if (!error.empty()) {
      ok = false;
      break;
    }
    full_rays = tracer->counts();
    tracer->reset_counts();

    const auto t_fov = std::chrono::steady_clock::now();
    foveated.plan(request, executor);  // the history's decision on the CPU (in the wall time)
    foveart::gpu::DeviceTraceFrame trace;
    XrResult engine_result = XR_SUCCESS;
    trace.engine =
        layer::xr_device_trace_engine(&foveart_gpu_engine_trace_rays_device, tracer.get(), &engine_result);
    trace.points = &tables->points;
    trace.view = view;
    trace.mapping = foveated.hand_off().mapping;
    trace.frame_index = request.frame_index;
    trace.sample_seed = foveated.hand_off().sample_seed;
    trace.rays_per_point = uint32_t(spp);
    trace.pixel_filter = settings.pixel_filter;
    foveart::gpu::EyeFrame frame = foveart::gpu::EyeFrame::of(*gpu_tables, foveated.hand_off(), true);
    frame.device = &trace;
    ok = gpu->submit_and_wait(
        [&](VkCommandBuffer cb) { return eye->record(cb, frame, VK_NULL_HANDLE, executor, &error); }, &error);
    const double fov_wall_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t_fov).count();
    foveart::gpu::StageTimes times;
    if (!ok || !eye->stage_times(&times)) break;
    fov_rays = tracer->counts();
    const foveart::gpu::DeviceTraceStatus status = eye->device_trace_status();
    if (status.invalid_components != 0) {
      error = std::to_string(status.invalid_components) + " invalid colour components";
      ok = false;
      break;
    }
    if (i == 0) continue;
    if (!(times.total_ms() > 0.0f)) {  // timed frames only: the warm-up may report none yet
      error = vulkan.name() + ": the foveated frame's stage timestamps read 0";
      ok = false;
      break;
    }
    const double fixed_ms = double(times.temporal_ms + times.encode_ms);  // the same passes on the same pixels
    full_trace.push_back(full_ms);
    fov_trace.push_back(double(times.trace_ms));
    gather.push_back(double(times.gather_ms));
    history.push_back(double(times.temporal_ms));
    encode.push_back(double(times.encode_ms));
    full_total.push_back(full_ms + fixed_ms);
    fov_total.push_back(double(times.total_ms()));
    ratio.push_back((full_ms + fixed_ms) / double(times.total_ms()));
    full_wall.push_back(full_wall_ms);
    fov_wall.push_back(fov_wall_ms);
    points.push_back(double(status.visible_points));
  }
  foveart::gpu::destroy_buffer(device.device, &full_out);
  if (!ok) return fail("frame failed: " + error);

  const double fov_ms = median(fov_total);
  const bool fits = fov_ms <= 7.0, fits_half = fov_ms <= 3.5;
  std::printf("%-10s | %9s %9s %9s %9s | %9s | %9s\n", "frame (ms)", "trace", "gather", "history", "encode", "total",
              "wall");
  std::printf("%-10s | %9.2f %9s %9.2f %9.2f | %9.2f | %9.2f\n", "full", median(full_trace), "-", median(history),
              median(encode), median(full_total), median(full_wall));
  std::printf("%-10s | %9.2f %9.2f %9.2f %9.2f | %9.2f | %9.2f\n", "foveated", median(fov_trace), median(gather),
              median(history), median(encode), fov_ms, median(fov_wall));
  std::printf("speedup (full / foveated, median of frame pairs): %.2fx; visible points %.0f; rays per eye full %u, "
              "foveated %.0f\n",
              median(ratio), median(points), view.width_px * view.height_px * uint32_t(spp), median(points) * spp);
  const auto rays_text = [](const foveart::engine::RayCounts& c) {
    return std::to_string(c.primary) + " " + std::to_string(c.shadow) + " " + std::to_string(c.reflection) + " " +
           std::to_string(c.refraction);
  };
  std::printf("rays traced, last frame (primary shadow reflection refraction): full %s; foveated %s\n",
              rays_text(full_rays).c_str(), rays_text(fov_rays).c_str());
  std::printf("foveated eye %.2f ms: %s 3.5 ms per eye (half a 70 Hz frame for two eyes), %s 7 ms per eye (two eyes "
              "in a 70 Hz frame)\n",
              fov_ms, fits_half ? "fits" : "misses", fits ? "fits" : "misses");
  if (!json_path.empty()) {
    nlohmann::json j = {
        {"command", "gpu_frame --scene " + scene_spec + " --size " + std::to_string(size[0]) + " " +
                        std::to_string(size[1]) + " --frames " + std::to_string(frames) + " --spp " +
                        std::to_string(spp) + " --k " + std::to_string(k) + " --temporal " + temporal},
        {"device", vulkan.name()},
        {"device_is_cpu", vulkan.is_cpu()},
        {"backend", tracer->backend_name()},
        {"backend_fallback", tracer->backend_fallback()},
        {"scene", tracer->scene().source},
        {"effects", foveart::engine::to_string(tracer->effects())},
        {"eye_px", {size[0], size[1]}},
        {"frames", frames},
        {"full_ms", {{"trace", median(full_trace)}, {"history", median(history)}, {"encode", median(encode)},
                     {"total", median(full_total)}, {"wall", median(full_wall)}}},
        {"foveated_ms", {{"trace", median(fov_trace)}, {"gather", median(gather)}, {"history", median(history)},
                         {"encode", median(encode)}, {"total", fov_ms}, {"wall", median(fov_wall)}}},
        {"speedup", median(ratio)},
        {"visible_points", median(points)},
        {"fits_7ms_per_eye", fits},
        {"fits_3_5ms_per_eye", fits_half},
        {"rays", {{"full", {full_rays.primary, full_rays.shadow, full_rays.reflection, full_rays.refraction}},
                  {"foveated", {fov_rays.primary, fov_rays.shadow, fov_rays.reflection, fov_rays.refraction}}}},
        {"table_bytes", gpu_tables->bytes()},
        {"memory", {{"device_local_bytes", memory_use.device_local_bytes},
                    {"host_visible_bytes", memory_use.host_visible_bytes},
                    {"texture_bytes", memory_use.texture_bytes},
                    {"fallback", tracer->memory_fallback()}}}};
    std::ofstream(json_path) << j.dump(2) << "\n";
  }
  return 0;
}
