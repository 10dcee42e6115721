// sim-motion-trace: the eye tracker's side of a scripted motion as a gaze trace.
//   sim-motion-trace [--motion builtin|FILE.csv] [--seed N] [--seconds S] --out TRACE.csv
// The trace holds, row for row, the gaze samples the simulated runtime shows under
// FOVEART_SIM_MOTION (120 Hz, +z forward, blinks invalid), so that
//   FOVEART_SIM_MOTION=builtin hello_foveated --gaze provider --gaze-provider replay:TRACE.csv
// plays the motion's head through the runtime and its gaze through the gaze provider.
#include <cstdio>
#include <string>

#include <CLI/CLI.hpp>

#include "motion_source.h"
#include "motion_trace.h"

int main(int argc, char** argv) {
  CLI::App cli{"sim-motion-trace: a scripted motion's gaze as a gaze provider trace"};
  std::string motion_spec = "builtin";
  uint64_t seed = 1;
  double seconds = 0.0;
  std::string out_path;
  cli.add_option("--motion", motion_spec, "'builtin' or a motion CSV (time_s,qx,...,valid[,saccade])")
      ->capture_default_str();
  cli.add_option("--seed", seed, "seed of the built-in motion")->capture_default_str();
  cli.add_option("--seconds", seconds, "trace length; the motion loops (0: one loop)")
      ->check(CLI::Range(0.0, 86400.0));
  cli.add_option("--out", out_path, "trace CSV to write")->required();
  CLI11_PARSE(cli, argc, argv);

  std::string error;
  const auto motion = foveart::sim::MotionSource::from_spec(motion_spec, seed, &error);
  if (!motion) {
    std::fprintf(stderr, "sim-motion-trace: %s\n", error.c_str());
    return 2;
  }
  const double duration_s =
      seconds > 0.0 ? seconds : static_cast<double>(motion->loop_period_ns()) * 1e-9;
  if (!foveart::sim::write_motion_gaze_trace_file(*motion, duration_s, out_path, &error)) {
    std::fprintf(stderr, "sim-motion-trace: %s\n", error.c_str());
    return 1;
  }
  std::printf("sim-motion-trace: %s, %.3f s of gaze at 120 Hz -> %s\n", motion->name().c_str(), duration_s,
              out_path.c_str());
  return 0;
}
