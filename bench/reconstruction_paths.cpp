// Per-eye reconstruction + TAA on both paths in one run (docs/gpu.md): the
// same frames of foveation::FoveatedView, reconstructed and accumulated by
// foveation on the CPU (all cores, the layer's executor) and by the compute
// shaders (gpu/) on a Vulkan device: a discrete or
// integrated GPU when there is one, else lavapipe (a CPU: there the ratio is
// what matters, not the absolute time). Median over --frames frames after one
// warm-up; GPU time from timestamps, CPU time from the wall clock. --temporal
// picks the history: "rays" (the GPU path's default: the render cache, the
// CPU's foveation::RayHistory against shaders/cache_*.comp, which on a still
// view holds its age limit's frames of rays) or "image" (reprojected).
//   reconstruction_paths [--size W H] [--k 5 20] [--frames N] [--interpolation nearest,msm,rbf]
//                        [--density-scale S] [--temporal image|rays]
// Tables come from $FOVEART_BENCH_CACHE (default /tmp/foveart_bench_cache).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "foveation/display_model.hpp"
#include "foveation/foveated_view.hpp"
#include "foveation/rgba8.hpp"
#include "foveation/temporal_mode.hpp"
#include "foveation/view_settings.hpp"
#include "gpu/reconstructor.hpp"
#include "headless_vulkan.hpp"

namespace {

namespace fv = foveart::foveation;
using foveart::gpu::EyeFrame;
using foveart::gpu::StageTimes;

int32_t gradient_engine(void*, const FoveartRayBatch* batch) {
  for (uint32_t i = 0; i < batch->ray_count; ++i) {
    batch->out_rgb[i * 3 + 0] = 0.5f + 0.4f * std::sin(batch->sample_px[i * 2] * 0.05f);
    batch->out_rgb[i * 3 + 1] = 0.5f + 0.4f * std::cos(batch->sample_px[i * 2 + 1] * 0.07f);
    batch->out_rgb[i * 3 + 2] = 0.3f;
  }
  return FOVEART_RESULT_SUCCESS;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App cli{"Per-eye reconstruction + temporal history on the CPU and the GPU path, in one run"};
  std::vector<int> size{1280, 1440};
  std::vector<int> ks{5, 20};
  std::vector<std::string> interpolation{"nearest", "msm", "rbf"};
  int frames = 20;
  double density_scale = 1.0;
  std::string temporal = "rays";
  cli.add_option("--size", size, "eye size W H")->expected(2)->check(CLI::Range(8, 8192))->capture_default_str();
  cli.add_option("--k", ks, "neighbours per pixel (MSM, RBF); nearest uses 1")->check(CLI::Range(1, 20))
      ->capture_default_str();
  cli.add_option("--interpolation", interpolation, "nearest, msm, rbf (comma-separated)")
      ->delimiter(',')
      ->check(CLI::IsMember({"nearest", "msm", "rbf"}))
      ->capture_default_str();
  cli.add_option("--frames", frames, "frames timed after one warm-up")->check(CLI::Range(1, 10000))
      ->capture_default_str();
  cli.add_option("--density-scale", density_scale, "point set density scale")->check(CLI::Range(0.25, 16.0))
      ->capture_default_str();
  cli.add_option("--temporal", temporal, "image | rays: the history both paths keep (rays: the GPU path's default)")
      ->check(CLI::IsMember({"image", "rays"}))
      ->capture_default_str();
  CLI11_PARSE(cli, argc, argv);
  fv::TemporalMode mode = fv::TemporalMode::rays;
  fv::parse_temporal_mode(temporal, &mode);
  std::vector<fv::InterpMethod> methods;
  for (const std::string& name : interpolation) methods.push_back(*fv::parse_method(name));

  foveart::layer::HeadlessVulkan vulkan(foveart::layer::DevicePreference::hardware_gpu, false);
  if (!vulkan.ok()) {
    std::fprintf(stderr, "reconstruction_paths: no Vulkan device with a compute queue\n");
    return 1;
  }
  std::string error;
  auto gpu = foveart::gpu::Reconstructor::create(vulkan.device(), &error);
  if (gpu == nullptr) {
    std::fprintf(stderr, "reconstruction_paths: %s cannot run the shaders: %s\n", vulkan.name().c_str(), error.c_str());
    return 1;
  }
  const char* env_cache = std::getenv("FOVEART_BENCH_CACHE");
  const std::filesystem::path cache = env_cache != nullptr ? env_cache : "/tmp/foveart_bench_cache";
  fv::Executor executor;
  std::printf("reconstruction_paths: %dx%d per eye, density scale %g, temporal \"%s\", %d frames; GPU: %s; CPU: %u "
              "threads\n",
              size[0], size[1], density_scale, temporal.c_str(), frames, vulkan.name().c_str(), executor.thread_count());
  std::printf("%-7s %3s | %12s %12s | %12s %12s %12s | %8s | gpu stages: scatter gather temporal encode (ms)\n",
              "method", "k", "cpu recon ms", "cpu +enc ms", "gpu recon ms", "gpu +enc ms", "gpu wall ms", "cpu/gpu");
  for (const fv::InterpMethod method : methods) {
    const std::string m(fv::method_name(method));
    for (int k : (method == fv::InterpMethod::nearest ? std::vector<int>{1} : ks)) {
      fv::PointSetKey key;
      key.display = fv::DisplayModel::from_fov(size[0], size[1], 90.0);
      key.display.scale = density_scale;
      fv::InterpOptions o;
      o.method = method;
      o.k = k;
      std::fprintf(stderr, "reconstruction_paths: tables for %s k %d (cached in %s) ...\n", m.c_str(), k, cache.c_str());
      const auto tables = fv::load_view_tables(cache, key, o, executor);
      fv::ViewSettings settings = fv::temporal_view_settings(mode, 1, 1);
      fv::FoveatedView cpu_view(tables, settings);
      settings.reconstruct_on_cpu = false;
      fv::FoveatedView gpu_view(tables, settings);
      const auto gpu_tables = gpu->upload_tables(tables, &error);
      auto eye = gpu_tables ? gpu->create_eye(uint32_t(size[0]), uint32_t(size[1]), &error) : nullptr;
      if (eye == nullptr) {
        std::fprintf(stderr, "reconstruction_paths: %s k %d: %s\n", m.c_str(), k, error.c_str());
        return 1;
      }
      std::vector<uint8_t> rgba(static_cast<std::size_t>(size[0]) * static_cast<std::size_t>(size[1]) * 4);
      std::vector<double> cpu_ms, cpu_enc_ms, gpu_ms, gpu_enc_ms, gpu_wall_ms, stage[4];
      for (int i = 0; i <= frames; ++i) {  // frame 0 warms up (and resets TAA)
        fv::FrameRequest r;
        r.view = fv::make_eye_view(0, uint32_t(size[0]), uint32_t(size[1]), fv::EyePose{}, -0.785f, 0.785f, 0.8f,
                                   -0.8f);
        r.gaze_px = {float(size[0] / 2 + i % 3), float(size[1] / 2)};
        r.frame_index = uint64_t(i + 1);
        const auto c = cpu_view.render(r, gradient_engine, nullptr, executor);
        const auto t0 = std::chrono::steady_clock::now();
        fv::encode_rgba8(cpu_view.image(), true, fv::DisplayTransform{}, rgba.data(), executor);
        const double enc = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        const auto g = gpu_view.render(r, gradient_engine, nullptr, executor);
        const EyeFrame f = EyeFrame::of(*gpu_tables, gpu_view.hand_off(), true);
        const auto t1 = std::chrono::steady_clock::now();
        const bool ok = gpu->submit_and_wait(
            [&](VkCommandBuffer cb) { return eye->record(cb, f, VK_NULL_HANDLE, executor, &error); }, &error);
        const double wall = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t1).count();
        StageTimes times;
        if (!ok || !c.ok() || !g.ok() || !eye->stage_times(&times)) {
          std::fprintf(stderr, "reconstruction_paths: frame %d failed: %s\n", i, error.c_str());
          return 1;
        }
        if (i == 0) continue;
        cpu_ms.push_back(c.reconstruct_ms + c.temporal_ms);
        cpu_enc_ms.push_back(c.reconstruct_ms + c.temporal_ms + enc);
        gpu_ms.push_back(double(times.scatter_ms + times.gather_ms + times.temporal_ms));
        gpu_enc_ms.push_back(double(times.total_ms()));
        gpu_wall_ms.push_back(wall);
        stage[0].push_back(double(times.scatter_ms));
        stage[1].push_back(double(times.gather_ms));
        stage[2].push_back(double(times.temporal_ms));
        stage[3].push_back(double(times.encode_ms));
      }
      std::printf("%-7s %3d | %12.2f %12.2f | %12.2f %12.2f %12.2f | %7.2fx | %.2f %.2f %.2f %.2f\n", m.c_str(), k,
                  median(cpu_ms), median(cpu_enc_ms), median(gpu_ms), median(gpu_enc_ms), median(gpu_wall_ms),
                  median(cpu_enc_ms) / median(gpu_enc_ms), median(stage[0]), median(stage[1]), median(stage[2]),
                  median(stage[3]));
      std::fflush(stdout);
    }
  }
  return 0;
}
