// Sample engine benchmarks: primary-ray throughput, the cost of each
// effect, proof that an absent effect costs nothing, and foveated-vs-full
// speedup. Run: <build>/bin/engine_bench [--benchmark_filter=...]
// Default scene, FOVE per-eye 1280x1440, centred gaze, all cores.
#include <engine/default_scene.hpp>
#include <engine/render.hpp>
#include <engine/tracer.hpp>


#include <benchmark/benchmark.h>
#include <foveation/executor.hpp>
#include <foveation/eye_rays.hpp>
#include <foveation/foveated_view.hpp>
#include <glm/common.hpp>

#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <memory>
#include <string>

using namespace foveart::engine;
namespace fv = foveart::foveation;

namespace {

// FOVEART_BENCH_THREADS=1 runs every render on the benchmark thread, so its
// CPU time (reported as cpu_ns/primary, cpu_ms) is the work itself even on a
// loaded machine; default: all cores.
int bench_threads() {
  const char* v = std::getenv("FOVEART_BENCH_THREADS");
  return v ? std::atoi(v) : 0;
}

// The one executor of this process (FOVEART_BENCH_THREADS threads, 0 = all).
fv::Executor& bench_executor() {
  static fv::Executor executor(static_cast<unsigned>(bench_threads()));
  return executor;
}

// The foveated frame of `fovea render --interpolation nearest`: FOVE preset, scale 1, one
// ray per point; tables from /tmp/foveart_bench_cache.
std::unique_ptr<fv::FoveatedView> nn_view() {
  fv::PointSetKey key;
  key.display = *fv::display_preset("fove");
  fv::InterpOptions nn;
  nn.method = fv::InterpMethod::nearest;
  nn.k = 1;
  return std::make_unique<fv::FoveatedView>(
      fv::load_view_tables(std::filesystem::path("/tmp/foveart_bench_cache"), key, nn, bench_executor()),
      fv::ViewSettings{});
}

fv::FrameRequest request_at(const FoveartEyeView& view, glm::vec2 gaze_px) {
  fv::FrameRequest r;
  r.view = view;
  r.gaze_px = gaze_px;
  return r;
}

double thread_cpu_s() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + static_cast<double>(ts.tv_nsec) * 1e-9;
}

// CPU time of all threads of the process: the work of a multithreaded frame,
// steadier than wall time on a shared machine.
double process_cpu_s() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + static_cast<double>(ts.tv_nsec) * 1e-9;
}

// An engine that traces nothing: what is left of a frame is the caller's bookkeeping.
extern "C" int32_t null_engine(void*, const FoveartRayBatch* batch) {
  for (uint32_t i = 0; i < 3 * batch->ray_count; ++i) batch->out_rgb[i] = 0.5f;
  return FOVEART_RESULT_SUCCESS;
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
  fv::ImageRgb img;
  tracer.reset_counts();
  double elapsed_s = 0.0, cpu_s = 0.0, proc_cpu_s = 0.0;
  for (auto _ : state) {
    const double c0 = thread_cpu_s();
    const double p0 = process_cpu_s();
    elapsed_s += render_full(&foveart_engine_trace_rays, &tracer, view, rs, &img, bench_executor()).trace_ms * 1e-3;
    cpu_s += thread_cpu_s() - c0;
    proc_cpu_s += process_cpu_s() - p0;
    benchmark::DoNotOptimize(img.rgb.data());
  }
  state.counters["proc_cpu_ms"] = proc_cpu_s * 1e3 / static_cast<double>(state.iterations());
  const RayCounts c = tracer.counts();
  state.SetItemsProcessed(static_cast<int64_t>(c.primary));  // items/s = primary rays/s
  state.counters["Mrays_total/s"] = benchmark::Counter(static_cast<double>(c.total()) / 1e6, benchmark::Counter::kIsRate);
  state.counters["shadow/primary"] = static_cast<double>(c.shadow) / static_cast<double>(c.primary);
  state.counters["reflection/primary"] = static_cast<double>(c.reflection) / static_cast<double>(c.primary);
  state.counters["refraction/primary"] = static_cast<double>(c.refraction) / static_cast<double>(c.primary);
  state.counters["lanes/packet"] = static_cast<double>(c.total()) / static_cast<double>(c.packets);
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

// The gazes measured: 0 the screen centre (the scene's hard case: dark pillars
// against the glowing wall under the ceiling lights), 1 the glass sphere,
// 2 the polished floor. Landmarks projected into the left eye's view.
glm::vec2 bench_gaze(const FoveartEyeView& view, int which) {
  if (which == 0) return glm::vec2(0.5f * static_cast<float>(view.width_px), 0.5f * static_cast<float>(view.height_px));
  const DefaultSceneLandmarks m = default_scene_landmarks();
  const foveart::foveation::EyePose pose = foveart::foveation::eye_pose(view);
  const glm::vec3 target = which == 1 ? m.glass_centre : m.floor_point;
  glm::vec2 px(0.0f);
  foveart::foveation::project_direction(foveart::foveation::eye_frustum(view), pose, target - pose.position_m, &px);
  return glm::round(px);
}

const char* gaze_name(int which) { return which == 0 ? "centre" : (which == 1 ? "glass" : "floor"); }

// Foveated (NN, scale 1, 1 ray per point) against full (1 ray per pixel), same
// scene and view; the tables are precomputed once outside the timed loop.
// Args: gaze (see bench_gaze), effects allowed (15 = the scene's kernel, 0 =
// primary rays only: isolates packet coherence from the ray mix), traversal
// (0 Embree's coherent one, the engine's; 1 its incoherent default).
void BM_Foveated(benchmark::State& state) {
  TracerOptions o;
  o.allowed = Effects::from_bits(static_cast<uint32_t>(state.range(1)));
  o.incoherent_traversal = state.range(2) != 0;
  auto t = make_tracer(make_default_scene(), o);
  const FoveartEyeView view = fove_eye_view(0, scene_head(t->scene()));
  const glm::vec2 gaze = bench_gaze(view, static_cast<int>(state.range(0)));
  state.SetLabel(std::string(gaze_name(static_cast<int>(state.range(0)))) + " " + std::to_string(static_cast<int>(gaze.x)) +
                 "," + std::to_string(static_cast<int>(gaze.y)) + " " + to_string(o.allowed) +
                 (o.incoherent_traversal ? " incoherent" : " coherent"));
  const auto foveated = nn_view();  // build (or load) the tables once
  double trace_ms = 0.0, reconstruct_ms = 0.0, cpu_s = 0.0, proc_cpu_s = 0.0;
  uint64_t points = 0;
  t->reset_counts();
  for (auto _ : state) {
    const double c0 = thread_cpu_s();
    const double p0 = process_cpu_s();
    const auto r = foveated->render(request_at(view, gaze), &foveart_engine_trace_rays, t.get(), bench_executor());
    cpu_s += thread_cpu_s() - c0;
    proc_cpu_s += process_cpu_s() - p0;
    if (!r.ok()) state.SkipWithError(r.message.c_str());
    trace_ms += r.select_ms + r.trace_ms;
    reconstruct_ms += r.reconstruct_ms;
    points = r.points;
  }
  const double n = static_cast<double>(state.iterations());
  const RayCounts c = t->counts();
  state.SetItemsProcessed(static_cast<int64_t>(c.primary));  // items/s = primary rays/s
  state.counters["points"] = static_cast<double>(points);
  state.counters["pixels/points"] = 1280.0 * 1440.0 / static_cast<double>(points);
  state.counters["rays/point"] = static_cast<double>(c.total()) / static_cast<double>(c.primary);
  state.counters["lanes/packet"] = static_cast<double>(c.total()) / static_cast<double>(c.packets);
  state.counters["frame_ms"] = (trace_ms + reconstruct_ms) / n;
  state.counters["trace_ms"] = trace_ms / n;
  state.counters["reconstruct_ms"] = reconstruct_ms / n;
  state.counters["cpu_ms"] = cpu_s * 1e3 / n;
  state.counters["proc_cpu_ms"] = proc_cpu_s * 1e3 / n;
}
BENCHMARK(BM_Foveated)
    ->Args({0, 15, 0})->Args({1, 15, 0})->Args({2, 15, 0})->Args({0, 0, 0})->Args({1, 0, 0})->Args({2, 0, 0})
    ->Args({0, 15, 1})->Args({0, 0, 1})
    ->Unit(benchmark::kMillisecond)->UseRealTime();

// Args: effects allowed (15 = the scene's kernel, 0 = primary only), traversal
// (0 coherent, 1 incoherent; as BM_Foveated).
void BM_Full(benchmark::State& state) {
  TracerOptions o;
  o.allowed = Effects::from_bits(static_cast<uint32_t>(state.range(0)));
  o.incoherent_traversal = state.range(1) != 0;
  state.SetLabel(to_string(o.allowed) + (o.incoherent_traversal ? " incoherent" : " coherent"));
  auto t = make_tracer(make_default_scene(), o);
  render_loop(state, *t);
  const RayCounts c = t->counts();
  state.counters["rays/pixel"] = static_cast<double>(c.total()) / static_cast<double>(c.primary);
}
BENCHMARK(BM_Full)->Args({15, 0})->Args({0, 0})->Args({15, 1})->Args({0, 1})->Unit(benchmark::kMillisecond)->UseRealTime();

// The bookkeeping alone, through an engine that traces nothing: 0 = full
// (ray generation, averaging), 1 = foveated at the centred gaze (visible points,
// disc samples, ray generation, colour slots, NN reconstruction).
void BM_Bookkeeping(benchmark::State& state) {
  auto t = make_tracer(make_default_scene());
  const FoveartEyeView view = fove_eye_view(0, scene_head(t->scene()));
  const bool foveated = state.range(0) == 1;
  state.SetLabel(foveated ? "foveated" : "full");
  const glm::vec2 gaze = bench_gaze(view, 0);
  const auto foveated_view = foveated ? nn_view() : nullptr;
  RenderSettings rs;
  fv::ImageRgb img;
  double cpu_s = 0.0, proc_cpu_s = 0.0, trace_ms = 0.0, reconstruct_ms = 0.0;
  uint64_t rays = 0;
  for (auto _ : state) {
    const double c0 = thread_cpu_s();
    const double p0 = process_cpu_s();
    if (foveated) {
      const fv::FrameResult r = foveated_view->render(request_at(view, gaze), &null_engine, nullptr, bench_executor());
      trace_ms += r.select_ms + r.trace_ms;
      reconstruct_ms += r.reconstruct_ms;
      rays = r.rays;
    } else {
      trace_ms += render_full(&null_engine, nullptr, view, rs, &img, bench_executor()).trace_ms;
      rays = uint64_t(view.width_px) * view.height_px;
    }
    cpu_s += thread_cpu_s() - c0;
    proc_cpu_s += process_cpu_s() - p0;
    benchmark::DoNotOptimize(img.rgb.data());
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["cpu_ms"] = cpu_s * 1e3 / n;
  state.counters["proc_cpu_ms"] = proc_cpu_s * 1e3 / n;
  state.counters["trace_ms"] = trace_ms / n;  // selection, rays, colour slots: what a traced ray carries
  state.counters["reconstruct_ms"] = reconstruct_ms / n;
  state.counters["trace_ns/ray"] = trace_ms * 1e6 / n / static_cast<double>(std::max<uint64_t>(rays, 1));
}
BENCHMARK(BM_Bookkeeping)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
