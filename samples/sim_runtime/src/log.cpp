#include "log.h"

#include <atomic>

namespace foveart::sim {
namespace {
std::atomic<int> g_level{1};
}

void set_log_level(int level) {
  g_level.store(level);
}
bool log_enabled(LogLevel level) {
  return static_cast<int>(level) <= g_level.load();
}

void log(LogLevel level, const std::string& message) {
  if (!log_enabled(level)) return;
  const char* tag = level == LogLevel::Error ? "error" : level == LogLevel::Info ? "info" : "debug";
  std::fprintf(stderr, "foveart-sim [%s] %s\n", tag, message.c_str());
}

}  // namespace foveart::sim
