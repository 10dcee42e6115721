// Leveled logging of the layer: stderr plus an optional log file, with
// "once" and rate-limited helpers for per-frame paths (a frame loop never floods the log).
#pragma once

#include <atomic>
#include <sstream>
#include <string>
#include <string_view>

namespace foveart::layer {

enum class LogLevel { Error = 0, Warn = 1, Info = 2, Debug = 3 };

// "error" | "warn" | "info" | "debug" -> level; false when the name is unknown.
bool parse_log_level(std::string_view name, LogLevel* out_level);
const char* log_level_name(LogLevel level);

// Process-wide sink. configure() is called at every xrCreateInstance (the last
// instance's config wins); thread-safe.
void log_configure(LogLevel level, const std::string& file_path);
bool log_enabled(LogLevel level);
void log_write(LogLevel level, std::string_view message);

template <class... Args>
void log(LogLevel level, const Args&... args) {
  if (!log_enabled(level)) return;
  std::ostringstream stream;
  (stream << ... << args);
  log_write(level, stream.str());
}

// A flag that lets one message through: for faults that repeat every frame.
class LogOnce {
 public:
  bool first() noexcept { return !fired_.exchange(true, std::memory_order_relaxed); }
  void reset() noexcept { fired_.store(false, std::memory_order_relaxed); }

 private:
  std::atomic<bool> fired_{false};
};

}  // namespace foveart::layer
