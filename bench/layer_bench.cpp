// Layer overhead per eye excluding the engine: one 1280x1440 FOVE eye, a
// constant-colour callback, NN / MSM k=5 / RBF k=5, TAA on and off.
// Time = wall, CPU = all threads of the process (the worker pool's too).
// Tables come from $FOVEART_BENCH_CACHE (default /tmp/foveart_bench_cache).
#include <cstdlib>
#include <map>
#include <memory>
#include <vector>

#include <benchmark/benchmark.h>

#include "foveation/display_model.hpp"
#include "view_pipeline.hpp"

namespace {

using foveart::layer::RendererSettings;

int32_t constant_engine(void*, const FoveartRayBatch* batch) {
  for (uint32_t i = 0; i < batch->ray_count * 3; ++i) batch->out_rgb[i] = 0.5f;
  return FOVEART_RESULT_SUCCESS;
}

std::shared_ptr<const foveart::layer::ViewTables> tables_for(const RendererSettings& s) {
  static std::map<int, std::shared_ptr<const foveart::layer::ViewTables>> cache;
  auto& slot = cache[static_cast<int>(s.interpolation)];
  if (!slot) {
    foveart::foveation::PointSetKey key;
    key.display = *foveart::foveation::display_preset("fove");
    key.seed = 1;
    key.k = foveart::layer::neighbor_count(s);
    const char* dir = std::getenv("FOVEART_BENCH_CACHE");
    slot = foveart::layer::load_view_tables(key, s, std::filesystem::path(dir ? dir : "/tmp/foveart_bench_cache"));
  }
  return slot;
}

void BM_EyeFramePath(benchmark::State& state) {
  RendererSettings s;
  s.trace_rays = &constant_engine;
  s.interpolation = static_cast<XrFoveatedInterpolationFOVEART>(state.range(0));
  s.k = 5;
  s.rays_per_point = 1;
  s.taa = state.range(1) != 0;
  foveart::layer::WorkerPool pool(0);
  foveart::layer::ViewPipeline pipeline(tables_for(s));
  foveart::layer::ViewRequest request;
  request.pose.orientation.w = 1.0f;
  request.fov = {-0.83f, 0.83f, 0.87f, -0.87f};
  request.width_px = 1280;
  request.height_px = 1440;
  request.gaze_px = {640, 720};
  std::vector<uint8_t> rgba(1280u * 1440u * 4u);
  double select = 0, interp = 0, taa = 0;
  for (auto _ : state) {
    ++request.frame_index;
    const auto out = pipeline.render(request, s, pool, rgba.data(), true);
    if (!out.ok) state.SkipWithError(out.message.c_str());
    select += double{out.select_ms};
    interp += double{out.interpolate_ms};
    taa += double{out.taa_ms};
    state.counters["points"] = out.points;
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["select_ms"] = select / n;
  state.counters["interpolate_ms"] = interp / n;
  state.counters["taa_ms"] = taa / n;
}
BENCHMARK(BM_EyeFramePath)
    ->ArgsProduct({{XR_FOVEATED_INTERPOLATION_NEAREST_FOVEART, XR_FOVEATED_INTERPOLATION_SHEPARD_FOVEART,
                    XR_FOVEATED_INTERPOLATION_RBF_FOVEART},
                   {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()  // CPU of all threads: comparable on a loaded machine
    ->UseRealTime()
    ->Iterations(5);

}  // namespace

BENCHMARK_MAIN();
