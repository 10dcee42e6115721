// Foveation core costs on the FOVE preset (targets: point set + table <= 10 s built,
// <= 0.5 s from cache; table memory). Run: build/bin/foveation_bench
//   --benchmark_format=json > out/foveation_bench.json
#include <benchmark/benchmark.h>

#include <filesystem>

#include <glm/gtc/quaternion.hpp>

#include "foveation/executor.hpp"
#include "foveation/gaze_mapping.hpp"
#include "foveation/eye_rays.hpp"
#include "foveation/point_set_cache.hpp"
#include "foveation/ray_cache.hpp"
#include "foveation/ray_samples.hpp"
#include "foveation/visible_points.hpp"

namespace fv = foveart::foveation;

namespace {

fv::Executor executor;  // all cores, started once

const fv::DisplayModel& fove() {
  static const fv::DisplayModel d = *fv::display_preset("fove");
  return d;
}

const fv::PointSet& fove_points() {
  static const fv::PointSet ps = fv::generate_point_set(fove(), 1);
  return ps;
}

void BM_GeneratePointSet(benchmark::State& state) {
  auto d = *fv::display_preset(state.range(0) == 0 ? "fove" : "thesis");
  for (auto _ : state) benchmark::DoNotOptimize(fv::generate_point_set(d, 1).size());
  state.counters["points"] = double(fv::generate_point_set(d, 1).size());
}
BENCHMARK(BM_GeneratePointSet)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->Iterations(1);

void BM_BuildNeighborTable(benchmark::State& state) {
  const auto& ps = fove_points();
  std::size_t bytes = 0;
  for (auto _ : state) bytes = fv::NeighborTable::build(ps, int(state.range(0)), executor).bytes();
  state.counters["table_MB"] = double(bytes) / 1e6;
}
BENCHMARK(BM_BuildNeighborTable)->Arg(20)->Arg(5)->Unit(benchmark::kMillisecond)->Iterations(1)->UseRealTime();

void BM_LoadFromCache(benchmark::State& state) {
  const auto dir = std::filesystem::temp_directory_path() / "foveart_bench_cache";
  fv::PointSetKey key{fove(), 1, 20};
  fv::load_or_build_tables(dir, key, executor);  // warm: build and store once
  for (auto _ : state) {
    auto t = fv::load_or_build_tables(dir, key, executor);
    if (!t.neighbors_from_cache) state.SkipWithError("table was not served from the cache");
  }
  std::filesystem::remove_all(dir);
}
BENCHMARK(BM_LoadFromCache)->Unit(benchmark::kMillisecond)->Iterations(3)->UseRealTime();

void BM_SelectVisiblePoints(benchmark::State& state) {
  const auto& ps = fove_points();
  const auto m = fv::map_gaze(1280, 1440, {640.0f, 720.0f});
  std::size_t n = 0;
  for (auto _ : state) n = fv::select_visible_points(ps, m).size();
  state.counters["visible"] = double(n);
}
BENCHMARK(BM_SelectVisiblePoints)->Unit(benchmark::kMillisecond);

void BM_RaySamples(benchmark::State& state) {
  const auto& ps = fove_points();
  const auto vis = fv::select_visible_points(ps, fv::map_gaze(1280, 1440, {640.0f, 720.0f}));
  for (auto _ : state) benchmark::DoNotOptimize(fv::generate_ray_samples(ps, vis, int(state.range(0)), 7, 1280).size());
  state.counters["rays"] = double(vis.size()) * double(state.range(0));
}
BENCHMARK(BM_RaySamples)->Arg(1)->Arg(4)->Unit(benchmark::kMillisecond);

// One frame of the render cache (TemporalMode::rays) at 320x360 while the
// head turns 0.3 deg a frame: project the kept rays, add the new rays,
// depth-test, filter and keep. Arg 0: frames of rays kept
// (RayCacheOptions::max_age_frames), arg 1: 0 box, 1 bspline2, arg 2: 0 the
// pixel grid (one new ray per pixel, the pixel filter), or a periphery's
// footprint F (one new ray per F x F pixels, and every pixel filtered from
// the rays at footprint F by filter_at, as beyond the pixel grid).
void BM_RayCacheFrame(benchmark::State& state) {
  constexpr std::uint32_t kW = 320, kH = 360;
  fv::RayCacheOptions options;
  options.max_age_frames = std::uint32_t(state.range(0));
  options.filter = state.range(1) == 0 ? fv::PixelFilter::box : fv::PixelFilter::bspline2;
  const std::uint32_t footprint_px = std::uint32_t(state.range(2));
  const std::uint32_t step_px = std::max(1u, footprint_px);  // new rays: one per step x step pixels
  const std::uint32_t rays_w = kW / step_px, rays_h = kH / step_px;
  fv::RayCache cache(options);
  fv::ImageRgb image;
  std::vector<glm::vec2> centres;
  std::vector<float> footprints, weights;
  std::vector<glm::vec3> rgb;
  if (footprint_px > 0)
    for (std::uint32_t y = 0; y < kH; ++y)
      for (std::uint32_t x = 0; x < kW; ++x) {
        centres.emplace_back(float(x) + 0.5f, float(y) + 0.5f);
        footprints.push_back(float(footprint_px));
      }
  std::uint64_t frame = 0;
  auto one_frame = [&] {
    fv::EyePose pose;
    pose.orientation = glm::angleAxis(glm::radians(0.3f * float(frame)), glm::vec3(0, 1, 0));
    const FoveartEyeView view = fv::make_eye_view(0, kW, kH, pose, -0.6f, 0.6f, 0.65f, -0.65f);
    cache.begin_frame(view, executor);
    const std::size_t first = cache.add_rays(std::size_t(rays_w) * rays_h);
    executor.parallel_chunks(std::size_t(rays_w) * rays_h, 4096, [&](std::size_t a, std::size_t b, unsigned) {
      for (std::size_t i = a; i < b; ++i) {
        const glm::vec2 corner = glm::vec2(float(i % rays_w), float(i / rays_w)) * float(step_px);
        const glm::vec2 q = footprint_px == 0 ? corner + fv::pixel_jitter(i, 0, frame, options.filter)
                                              : corner + fv::pixel_jitter(i, 0, frame, fv::PixelFilter::box) * float(step_px);
        cache.set_ray(first + i, q, glm::vec3(0.5f), 3.0f + 0.001f * float(i % 97));
      }
    });
    if (footprint_px > 0) cache.filter_at(centres, footprints, executor, &rgb, &weights);
    cache.resolve(executor, &image);
    ++frame;
  };
  for (std::int64_t i = 0; i < state.range(0); ++i) one_frame();  // the cache full
  for (auto _ : state) one_frame();
  state.counters["rays_kept"] = double(cache.size());
}
BENCHMARK(BM_RayCacheFrame)
    ->Args({8, 0, 0})
    ->Args({32, 0, 0})
    ->Args({32, 1, 0})
    ->Args({32, 1, 2})
    ->Args({32, 1, 4})
    ->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
