// Sample engine benchmarks (issue 4): primary-ray throughput, the cost of each
// effect, proof that an absent effect costs nothing, and foveated-vs-full
// speedup. Run: <build>/bin/engine_bench [--benchmark_filter=...]
// Default scene, FOVE per-eye 1280x1440, centred gaze, all cores.
#include <engine/default_scene.hpp>
#include <engine/render.hpp>
#include <engine/tracer.hpp>

#include <render_foveated.hpp>

#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <memory>

using namespace foveart::engine;

namespace {

// FOVEART_BENCH_THREADS=1 runs every render on the benchmark thread, so its
// CPU time (reported as cpu_ns/primary, cpu_ms) is the work itself even on a
// loaded machine; default: all cores.
int bench_threads() {
  const char* v = std::getenv("FOVEART_BENCH_THREADS");
  return v ? std::atoi(v) : 0;
}

double thread_cpu_s() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + static_cast<double>(ts.tv_nsec) * 1e-9;
}

std::unique_ptr<Tracer> make_tracer(Scene scene, TracerOptions options = {}) {
  std::string error;
  auto t = Tracer::create(std::move(scene), options, &error);
  if (!t) std::fprintf(stderr, "engine_bench: %s\n", error.c_str());
  return t;
}

// The default scene's geometry with every effect removed from its data: rough,
// opaque, untextured materials and no lights.
Scene plain_default_scene() {
  Scene s = make_default_scene();
  for (Material& m : s.materials) {
    m.roughness = 1.0f;
    m.transmission = 0.0f;
    m.base_color_texture = -1;
  }
  s.lights.clear();
  return s;
}

void render_loop(benchmark::State& state, Tracer& tracer, int spp = 1) {
  const FoveartEyeView view = fove_eye_view(0, scene_head(tracer.scene()));
  RenderSettings rs;
  rs.spp = spp;
  rs.threads = bench_threads();
  Image img;
  tracer.reset_counts();
  double elapsed_s = 0.0, cpu_s = 0.0;
  for (auto _ : state) {
    const double c0 = thread_cpu_s();
    elapsed_s += render_full(&foveart_engine_trace_rays, &tracer, view, rs, &img).trace_ms * 1e-3;
    cpu_s += thread_cpu_s() - c0;
    benchmark::DoNotOptimize(img.rgb.data());
  }
  const RayCounts c = tracer.counts();
  state.SetItemsProcessed(static_cast<int64_t>(c.primary));  // items/s = primary rays/s
  state.counters["Mrays_total/s"] = benchmark::Counter(static_cast<double>(c.total()) / 1e6, benchmark::Counter::kIsRate);
  state.counters["shadow/primary"] = static_cast<double>(c.shadow) / static_cast<double>(c.primary);
  state.counters["reflection/primary"] = static_cast<double>(c.reflection) / static_cast<double>(c.primary);
  state.counters["refraction/primary"] = static_cast<double>(c.refraction) / static_cast<double>(c.primary);
  state.counters["ns/primary"] = elapsed_s * 1e9 / static_cast<double>(c.primary);
  state.counters["cpu_ns/primary"] = cpu_s * 1e9 / static_cast<double>(c.primary);
  state.counters["cpu_ms"] = cpu_s * 1e3 / static_cast<double>(state.iterations());
}

// Primary rays only (kernel with every effect compiled out).
void BM_PrimaryOnly(benchmark::State& state) {
  TracerOptions o;
  o.allowed = Effects::none();
  auto t = make_tracer(make_default_scene(), o);
  render_loop(state, *t);
}
BENCHMARK(BM_PrimaryOnly)->Unit(benchmark::kMillisecond)->UseRealTime();

// One effect at a time on top of primary rays, then all of them: the price list.
void BM_Effect(benchmark::State& state) {
  TracerOptions o;
  o.allowed = Effects::from_bits(static_cast<uint32_t>(state.range(0)));
  state.SetLabel(to_string(o.allowed));
  auto t = make_tracer(make_default_scene(), o);
  render_loop(state, *t);
}
BENCHMARK(BM_Effect)->Arg(1)->Arg(2)->Arg(4)->Arg(8)->Arg(15)->Unit(benchmark::kMillisecond)->UseRealTime();

// Same geometry, no effect in the scene data: the scene's own (specialised)
// kernel, the primary-only kernel, and the all-effects kernel that skips at run time.
void BM_SceneWithoutEffects(benchmark::State& state) {
  TracerOptions o;
  if (state.range(0) == 1) o.allowed = Effects::none();
  if (state.range(0) == 2) o.generic_kernel = true;
  state.SetLabel(state.range(0) == 0 ? "specialised" : (state.range(0) == 1 ? "primary-only" : "generic"));
  auto t = make_tracer(plain_default_scene(), o);
  render_loop(state, *t);
}
BENCHMARK(BM_SceneWithoutEffects)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

#ifdef FOVEART_HAVE_FOVEATION
// Foveated (NN, scale 1, 1 ray per point) against full (1 ray per pixel), same
// scene and view; the tables are precomputed once outside the timed loop.
void BM_Foveated(benchmark::State& state) {
  auto t = make_tracer(make_default_scene());
  const FoveartEyeView view = fove_eye_view(0, scene_head(t->scene()));
  foveart::tools::FoveatedRequest req;
  req.gaze_px = glm::vec2(640.0f, 720.0f);
  req.cache_dir = "/tmp/foveart_bench_cache";
  req.threads = bench_threads();
  foveart::tools::FoveatedRenderer renderer(view, req);  // build (or load) the tables once
  if (!renderer.error().empty()) state.SkipWithError(renderer.error().c_str());
  Image img;
  double trace_ms = 0.0, reconstruct_ms = 0.0, cpu_s = 0.0;
  uint64_t points = 0;
  for (auto _ : state) {
    const double c0 = thread_cpu_s();
    const auto r = renderer.render(*t, req.gaze_px, &img);
    cpu_s += thread_cpu_s() - c0;
    trace_ms += r.trace_ms;
    reconstruct_ms += r.reconstruct_ms;
    points = r.points;
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["points"] = static_cast<double>(points);
  state.counters["pixels/points"] = 1280.0 * 1440.0 / static_cast<double>(points);
  state.counters["frame_ms"] = (trace_ms + reconstruct_ms) / n;
  state.counters["trace_ms"] = trace_ms / n;
  state.counters["reconstruct_ms"] = reconstruct_ms / n;
  state.counters["cpu_ms"] = cpu_s * 1e3 / n;
}
BENCHMARK(BM_Foveated)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_Full(benchmark::State& state) {
  auto t = make_tracer(make_default_scene());
  render_loop(state, *t);
}
BENCHMARK(BM_Full)->Unit(benchmark::kMillisecond)->UseRealTime();
#endif

}  // namespace

BENCHMARK_MAIN();
