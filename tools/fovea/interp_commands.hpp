// `fovea interpolate` and `fovea reconstruct`: registration with the
// fovea tool and the testable cores behind them.
#pragma once

#include <cstdint>
#include <iosfwd>
#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace foveart::fovea {

// Registration with the fovea tool (declared for main.cpp in commands.hpp).
void register_interpolate(CLI::App& app);
void register_reconstruct(CLI::App& app);

// --- fovea interpolate ---------------------------------------------------------
struct InterpolateArgs {
  std::string interpolation = "msm";  // nearest | msm | rbf | rbf-gauss
  int k = 5;
  double shape = 0.0;  // 0 = kernel default
  bool no_constant = false;
  std::string rbf_clamp = "block";  // off | taps | block (foveation::RbfClamp; block = taps here)
  std::string samples_file;
  std::string queries_file;
};
// Reads the two CSV files, writes one value per query line to `out`. Returns the
// exit code; on error writes one "fovea interpolate: ..." line to `err`.
int run_interpolate(const InterpolateArgs& args, std::ostream& out, std::ostream& err);

// Parses CSV text of rows with `fields` numbers each (a first header line is
// allowed). Returns an error message (with file and line), empty on success.
std::string parse_csv_rows(std::istream& in, const std::string& name, int fields, std::vector<double>& values);

// --- fovea reconstruct ---------------------------------------------------------
struct ReconstructArgs {
  std::string image;
  std::string preset = "fove";
  std::string gaze;  // "X,Y" screen pixels; empty = centre
  std::string interpolation = "msm";  // nearest | msm | rbf | rbf-gauss
  int k = 5;
  double density_scale = 1.0;
  int rays_per_point = 8;
  std::string out;
  bool json = false;
  int frames = 1;
  bool jitter = false;
  std::uint64_t seed = 1;
  std::string cache_dir;
  bool no_cache = false;
  int threads = 0;
  double shape = 0.0;
  bool no_constant = false;
  std::string weights;  // f16 | f32 | empty (the library's choice)
  std::string rbf_clamp = "block";  // off | taps | block (foveation::RbfClamp)
};

// Runs the whole pipeline; returns the exit code (errors as one line on `err`).
int run_reconstruct(const ReconstructArgs& args, std::ostream& out, std::ostream& err);

}  // namespace foveart::fovea
