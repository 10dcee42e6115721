// Layer overhead per eye excluding the engine: one 1280x1440 FOVE eye through
// the frame the layer runs (foveation::FoveatedView) with a constant-colour
// callback, then the RGBA8 encode for the swapchain; NN / MSM k=5 / RBF k=5,
// temporal history on and off; and the encode alone. Time = wall, CPU = all threads of the process.
// Tables come from $FOVEART_BENCH_CACHE (default /tmp/foveart_bench_cache).
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <vector>

#include <benchmark/benchmark.h>

#include "foveation/display_model.hpp"
#include "foveation/executor.hpp"
#include "foveation/foveated_view.hpp"
#include "foveation/rgba8.hpp"

namespace {

namespace fv = foveart::foveation;

int32_t constant_engine(void*, const FoveartRayBatch* batch) {
  for (uint32_t i = 0; i < batch->ray_count * 3; ++i) batch->out_rgb[i] = 0.5f;
  return FOVEART_RESULT_SUCCESS;
}

fv::Executor& executor() {
  static fv::Executor all_cores;  // as the layer: one per renderer, worker_threads = 0
  return all_cores;
}

std::shared_ptr<const fv::ViewTables> tables_for(fv::InterpMethod method) {
  static std::map<fv::InterpMethod, std::shared_ptr<const fv::ViewTables>> cache;
  auto& slot = cache[method];
  if (!slot) {
    fv::PointSetKey key;
    key.display = *fv::display_preset("fove");
    fv::InterpOptions o;
    o.method = method;
    o.k = method == fv::InterpMethod::nearest ? 1 : 5;
    const char* dir = std::getenv("FOVEART_BENCH_CACHE");
    slot = fv::load_view_tables(std::filesystem::path(dir ? dir : "/tmp/foveart_bench_cache"), key, o, executor());
  }
  return slot;
}

// Args: method (0 NN, 1 MSM, 2 RBF-MQ), temporal history (0 off / 1 image).
void BM_EyeFramePath(benchmark::State& state) {
  const fv::InterpMethod methods[] = {fv::InterpMethod::nearest, fv::InterpMethod::msm, fv::InterpMethod::rbf};
  const bool temporal = state.range(1) != 0;
  fv::ViewSettings settings;  // as the layer sets them
  settings.temporal = temporal ? fv::TemporalMode::image : fv::TemporalMode::off;
  settings.new_jitter_each_frame = temporal;
  fv::FoveatedView view(tables_for(methods[state.range(0)]), settings);
  fv::FrameRequest request;
  request.view = fv::make_eye_view(0, 1280, 1440, fv::EyePose{}, -0.83f, 0.83f, 0.87f, -0.87f);
  request.gaze_px = {640, 720};
  std::vector<uint8_t> rgba(1280u * 1440u * 4u);
  double select = 0, trace = 0, interp = 0, temporal_ms = 0, encode = 0;
  for (auto _ : state) {
    ++request.frame_index;
    const auto out = view.render(request, &constant_engine, nullptr, executor());
    if (!out.ok()) state.SkipWithError(out.message.c_str());
    const auto t0 = std::chrono::steady_clock::now();
    fv::encode_rgba8(view.image(), true, fv::DisplayTransform{}, rgba.data(), executor());
    encode += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    select += out.select_ms;
    trace += out.trace_ms;
    interp += out.reconstruct_ms;
    temporal_ms += out.temporal_ms;
    state.counters["points"] = out.points;
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["select_ms"] = select / n;
  state.counters["trace_ms"] = trace / n;
  state.counters["reconstruct_ms"] = interp / n;
  state.counters["temporal_ms"] = temporal_ms / n;
  state.counters["encode_ms"] = encode / n;
}
// Stage 6 alone on one FOVE eye of radiance from 0 to 4 (the tone map's
// roll-off included), PBR Neutral, sRGB, on the layer's executor. Arg 0: the
// per-pixel DisplayTransform::srgb8() call in the loop (the encode before
// rows were encoded as runs); arg 1: encode_rgba8, the curve chosen per run.
void BM_EncodeRgba8(benchmark::State& state) {
  fv::ImageRgb image(1280, 1440);
  uint32_t x = 1;
  for (float& v : image.rgb) v = float((x = x * 1664525u + 1013904223u) >> 8) / float(1 << 22);
  const fv::DisplayTransform display;
  std::vector<uint8_t> rgba(image.pixel_count() * 4);
  const std::size_t width = std::size_t(image.width_px);
  for (auto _ : state) {
    if (state.range(0) == 0) {
      executor().parallel_chunks(std::size_t(image.height_px), 64, [&](std::size_t y0, std::size_t y1, unsigned) {
        for (std::size_t i = y0 * width; i < y1 * width; ++i) {
          const float* p = image.rgb.data() + i * 3;
          const glm::u8vec3 b = display.srgb8(glm::vec3(p[0], p[1], p[2]));
          rgba[i * 4] = b.r, rgba[i * 4 + 1] = b.g, rgba[i * 4 + 2] = b.b, rgba[i * 4 + 3] = 255;
        }
      });
    } else {
      fv::encode_rgba8(image, true, display, rgba.data(), executor());
    }
    benchmark::DoNotOptimize(rgba.data());
  }
  state.SetLabel(state.range(0) == 0 ? "per-pixel srgb8()" : "encode_rgba8 (runs)");
}
BENCHMARK(BM_EncodeRgba8)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(1.0);

BENCHMARK(BM_EyeFramePath)
    ->ArgsProduct({{0, 1, 2}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()  // CPU of all threads: comparable on a loaded machine
    ->UseRealTime()
    ->Iterations(5);

}  // namespace

BENCHMARK_MAIN();
