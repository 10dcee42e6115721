// The perceptual metric (eval/perceptual_metric.hpp) on one 1280x1440 FOVE eye: a textured
// reference against a copy with noise, the gaze at the centre, on an executor of 1 or 2 threads
// (Arg 0; the lab machine's 2 cores). Arg 1: 0 the same gaze every time (the price list's case:
// the gaze tables are reused), 1 a new gaze every time (they are rebuilt). Time = wall.
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>

#include <benchmark/benchmark.h>

#include "eval/perceptual_metric.hpp"
#include "foveation/display_model.hpp"
#include "foveation/executor.hpp"

namespace {

namespace fv = foveart::foveation;
using foveart::eval::PerceptualMetric;

constexpr int kWidth = 1280, kHeight = 1440;

// Deterministic texture: sinusoids of a few frequencies plus a hash's noise of amplitude `noise`.
fv::ImageRgb texture(double noise, std::uint32_t seed) {
  fv::ImageRgb img(kWidth, kHeight);
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      std::uint32_t h = (std::uint32_t(x) * 73856093u) ^ (std::uint32_t(y) * 19349663u) ^ (seed * 83492791u);
      h ^= h >> 13, h *= 0x5bd1e995u, h ^= h >> 15;
      const double n = noise * (double(h & 0xffffu) / 65535.0 - 0.5);
      const double v = 0.45 + 0.2 * std::sin(0.05 * x) * std::cos(0.031 * y) + 0.1 * std::sin(0.4 * x + 0.3 * y) + n;
      for (int c = 0; c < 3; ++c) img.at(x, y)[c] = float(v * (0.8 + 0.2 * c));
    }
  return img;
}

struct Fixture {
  PerceptualMetric metric;
  fv::ImageRgb reference = texture(0.0, 1), test = texture(0.04, 2);
  Fixture() {
    foveart::eval::PerceptualDisplay d;
    d.pixels_per_deg = fv::display_preset("fove")->view_distance_px * M_PI / 180.0;
    std::string error;
    if (!PerceptualMetric::create(d, kWidth, kHeight, {}, metric, error)) std::abort();
  }
};

const Fixture& fixture() {
  static const Fixture f;
  return f;
}

void BM_PerceptualMetricFoveEye(benchmark::State& state) {
  const Fixture& f = fixture();
  fv::Executor ex(static_cast<unsigned>(state.range(0)));
  const bool new_gaze = state.range(1) != 0;
  foveart::eval::PerceptualResult out;
  std::string error;
  float shift = 0.0f;
  for (auto _ : state) {
    if (new_gaze) shift = shift == 0.0f ? 1.0f : 0.0f;
    if (!f.metric.evaluate(f.test, f.reference, {640.0f + shift, 720.0f}, &ex, out, error))
      state.SkipWithError(error.c_str());
    // Not DoNotOptimize(out.p_mean): on a double, GCC 12 with this benchmark's "+m,r" constraint
    // left garbage in it (seen here); the map's pointer is enough.
    benchmark::DoNotOptimize(out.p_detect.data());
  }
  state.SetLabel("p_mean " + std::to_string(out.p_mean) + ", p_max " + std::to_string(out.p_max));
}

}  // namespace

BENCHMARK(BM_PerceptualMetricFoveEye)
    ->ArgsProduct({{1, 2}, {0, 1}})
    ->ArgNames({"threads", "new_gaze"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MinTime(2.0);

BENCHMARK_MAIN();
