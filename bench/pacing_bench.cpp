// How punctual the real clock lets the paced threads be, on this machine (the
// pass/fail tests run the same code on virtual clocks, tests/common/manual_clock.hpp
// and FOVEART_SIM_CLOCK=virtual). Counters, per run:
//   SimProvider120Hz: samples in 2 s (nominal 240), host interval p50 and p99 (ms);
//   ProviderStop: stop() of a streaming provider (its sleeps last <= 50 ms);
//   SimClock70HzGrid: the runtime's real clock sleeping to a 70 Hz grid, as
//   xrWaitFrame does: mean interval and p99 lateness past each slot (ms).
#include <benchmark/benchmark.h>

#include <chrono>
#include <thread>
#include <vector>

#include "foveation/percentile.hpp"
#include "gaze_provider/backends.h"
#include "sim_clock.h"

namespace {

using foveart::foveation::percentile;
using namespace std::chrono_literals;
namespace gaze = foveart::gaze;

void SimProvider120Hz(benchmark::State& state) {
  for (auto _ : state) {
    gaze::CreateResult created = gaze::create_gaze_provider("sim:5");
    if (!created) {
      state.SkipWithError(created.error.c_str());
      return;
    }
    std::string error;
    created.provider->start(&error);
    std::vector<gaze::GazeSample> all, buf(256);
    const auto end = std::chrono::steady_clock::now() + 2s;
    while (std::chrono::steady_clock::now() < end) {
      std::this_thread::sleep_for(10ms);
      for (std::size_t n; (n = created.provider->read_raw(buf)) > 0;)
        all.insert(all.end(), buf.begin(), buf.begin() + std::ptrdiff_t(n));
    }
    created.provider->stop();
    std::vector<double> host_ms;
    for (std::size_t i = 1; i < all.size(); ++i)
      host_ms.push_back(double(all[i].host_time_ns - all[i - 1].host_time_ns) * 1e-6);
    state.counters["samples_in_2s"] = double(all.size());
    state.counters["host_interval_p50_ms"] = percentile(host_ms, 50);
    state.counters["host_interval_p99_ms"] = percentile(host_ms, 99);
  }
}
BENCHMARK(SimProvider120Hz)->Iterations(1)->Unit(benchmark::kMillisecond)->UseRealTime();

void ProviderStop(benchmark::State& state) {
  gaze::CreateResult created = gaze::create_gaze_provider("sim");
  if (!created) {
    state.SkipWithError(created.error.c_str());
    return;
  }
  std::string error;
  for (auto _ : state) {
    state.PauseTiming();
    created.provider->start(&error);
    std::this_thread::sleep_for(50ms);
    state.ResumeTiming();
    created.provider->stop();
  }
}
BENCHMARK(ProviderStop)->Iterations(20)->Unit(benchmark::kMillisecond)->UseRealTime();

void SimClock70HzGrid(benchmark::State& state) {
  constexpr int64_t kPeriodNs = 14'285'714;
  constexpr int kFrames = 36;
  for (auto _ : state) {
    foveart::sim::SimClock clock(false);
    const int64_t origin = clock.now_ns();
    std::vector<double> late_ms;
    int64_t first = 0, last = 0;
    for (int k = 1; k <= kFrames; ++k) {
      const int64_t slot = origin + k * kPeriodNs;
      clock.sleep_until_ns(slot);
      const int64_t woke = clock.now_ns();
      late_ms.push_back(double(woke - slot) * 1e-6);
      if (k == 1) first = woke;
      last = woke;
    }
    state.counters["mean_interval_ms"] = double(last - first) * 1e-6 / (kFrames - 1);
    state.counters["late_p99_ms"] = percentile(late_ms, 99);
  }
}
BENCHMARK(SimClock70HzGrid)->Iterations(1)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
