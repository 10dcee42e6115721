#include "toolkit/progress.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstdio>

namespace foveart::toolkit {

Progress::Progress(std::string label)
    : label_(std::move(label)), enabled_(::isatty(STDERR_FILENO) == 1),
      start_(std::chrono::steady_clock::now()), last_draw_(start_) {}

Progress::~Progress() {
  if (drawn_) std::fprintf(stderr, "\r%s: done%30s\n", label_.c_str(), "");
}

void Progress::update(double fraction) {
  if (!enabled_) return;
  const auto now = std::chrono::steady_clock::now();
  if (now - start_ < std::chrono::seconds(1)) return;
  if (drawn_ && now - last_draw_ < std::chrono::milliseconds(100)) return;
  last_draw_ = now;
  drawn_ = true;
  const int width = 30;
  const double f = std::clamp(fraction, 0.0, 1.0);
  const int filled = int(f * width);
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  std::fprintf(stderr, "\r%s [%-*s] %3d%% %.1fs", label_.c_str(), width,
               std::string(std::size_t(filled), '#').c_str(), int(f * 100.0), elapsed);
  std::fflush(stderr);
}

}  // namespace foveart::toolkit
