// A progress indicator for long work, on stderr, only when stderr is a terminal
// and only once the work has taken more than a second.
#pragma once

#include <chrono>
#include <string>

namespace foveart::toolkit {

class Progress {
 public:
  explicit Progress(std::string label);
  ~Progress();  // finishes the line if anything was drawn
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  // fraction in [0, 1]; cheap to call often (redraws at most 10 times a second).
  void update(double fraction);

 private:
  std::string label_;
  bool enabled_;
  bool drawn_ = false;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_draw_;
};

}  // namespace foveart::toolkit
